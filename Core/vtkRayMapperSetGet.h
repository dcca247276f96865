// Set macros for the numeric properties of the RayMappers mappers and filters.
//
// VTK's vtkSetClampMacro lets NaN through (NaN < min and NaN > max are both false) and
// clamps out-of-range values silently; vtkSetMacro checks nothing. A NaN property reaches
// the kernels' float arithmetic and poisons every pixel it touches. These macros
//   - reject NaN and infinity: one warning naming the property and the value ("Radius nan
//     is not a number: ignored; Radius stays 1."); the property keeps its value (an
//     infinite value means as little as NaN, and clamping it would make the largest
//     value out of garbage, e.g. a radius default that ParaView computes from infinite
//     bounds);
//   - clamp a value outside [min, max] to the nearest bound with one warning naming the
//     property, the value and the range ("Radius -1 is outside [0, 1e+15]: clamped to 0.").
// The warning comes from the object itself (vtkWarningWithObjectMacro: its class name
// prefixes the text, observers of its WarningEvent see it, and ParaView's output window
// shows it for a value set from pvpython, whatever the XML domains allow).
//
// Header-only (vtkObject and vtkSetGet.h) in the private module RayMappers::Core that the
// mappers, the filters and the representations share; VTK's wrappers expand the macros as
// they expand VTK's own.
#ifndef vtkRayMapperSetGet_h
#define vtkRayMapperSetGet_h

#include "vtkObject.h"
#include "vtkSetGet.h"

#include <cmath>
#include <type_traits>

/// The largest length or factor on lengths a property may have: the kernels'
/// raymappers::MaxLength (Mappers/Common/Limits.h says why; vtkRayMapperCore.cxx asserts
/// at compile time that the two are equal, since a public header cannot include a kernel's).
#define VTK_RAYMAPPER_LENGTH_MAX 1e15

namespace vtkRayMapperSetGet
{

/// The value a setter of property `name` stores: false (the property keeps its value)
/// for NaN or infinity, else `value` clamped to [min, max]; each case with a warning from
/// `self`.
template<typename T>
bool Accept(vtkObject* self, const char* name, T& value, T min, T max, T current)
{
  if constexpr (std::is_floating_point_v<T>)
  {
    if (!std::isfinite(value))
    {
      vtkWarningWithObjectMacro(self,
        << name << " " << value << (std::isnan(value) ? " is not a number" : " is not finite")
        << ": ignored; " << name << " stays " << current << ".");
      return false;
    }
  }
  if (value < min || value > max)
  {
    const T clamped = value < min ? min : max;
    vtkWarningWithObjectMacro(self,
      << name << " " << value << " is outside [" << min << ", " << max << "]: clamped to "
      << clamped << ".");
    value = clamped;
  }
  return true;
}

/// As Accept for every component of a vector property: a NaN or infinite component rejects
/// the whole vector (one warning), components outside [min, max] are clamped (one warning).
template<typename T, int N>
bool AcceptVector(vtkObject* self, const char* name, T (&value)[N], T min, T max)
{
  if constexpr (std::is_floating_point_v<T>)
  {
    for (int i = 0; i < N; ++i)
    {
      if (!std::isfinite(value[i]))
      {
        vtkWarningWithObjectMacro(self,
          << name << " has a component that is "
          << (std::isnan(value[i]) ? "not a number" : "not finite") << " (component " << i
          << "): ignored; " << name << " keeps its value.");
        return false;
      }
    }
  }
  bool clamped = false;
  for (int i = 0; i < N; ++i)
  {
    if (value[i] < min || value[i] > max)
    {
      value[i] = value[i] < min ? min : max;
      clamped = true;
    }
  }
  if (clamped)
  {
    vtkWarningWithObjectMacro(self,
      << name << " has components outside [" << min << ", " << max
      << "]: they are clamped to the range.");
  }
  return true;
}

}

/// vtkSetClampMacro that rejects NaN and infinity and warns when it clamps (see above).
#define vtkRayMapperSetClampMacro(name, type, min, max)                                           \
  virtual void Set##name(type _arg)                                                                \
  {                                                                                                \
    if (vtkRayMapperSetGet::Accept<type>(this, #name, _arg, min, max, this->name) &&               \
      this->name != _arg)                                                                          \
    {                                                                                              \
      this->name = _arg;                                                                           \
      this->Modified();                                                                            \
    }                                                                                              \
  }                                                                                                \
  virtual type Get##name##MinValue() { return min; }                                               \
  virtual type Get##name##MaxValue() { return max; }

/// vtkSetVector3Macro with the checks of vtkRayMapperSetClampMacro on every component.
#define vtkRayMapperSetVector3ClampMacro(name, type, min, max)                                    \
  virtual void Set##name(type _arg1, type _arg2, type _arg3)                                       \
  {                                                                                                \
    type _arg[3] = { _arg1, _arg2, _arg3 };                                                        \
    if (vtkRayMapperSetGet::AcceptVector<type, 3>(this, #name, _arg, min, max) &&                  \
      (this->name[0] != _arg[0] || this->name[1] != _arg[1] || this->name[2] != _arg[2]))          \
    {                                                                                              \
      this->name[0] = _arg[0];                                                                     \
      this->name[1] = _arg[1];                                                                     \
      this->name[2] = _arg[2];                                                                     \
      this->Modified();                                                                            \
    }                                                                                              \
  }                                                                                                \
  virtual void Set##name(const type _arg[3]) { this->Set##name(_arg[0], _arg[1], _arg[2]); }

/// vtkSetVector2Macro with the checks of vtkRayMapperSetClampMacro on every component.
#define vtkRayMapperSetVector2ClampMacro(name, type, min, max)                                    \
  virtual void Set##name(type _arg1, type _arg2)                                                   \
  {                                                                                                \
    type _arg[2] = { _arg1, _arg2 };                                                               \
    if (vtkRayMapperSetGet::AcceptVector<type, 2>(this, #name, _arg, min, max) &&                  \
      (this->name[0] != _arg[0] || this->name[1] != _arg[1]))                                      \
    {                                                                                              \
      this->name[0] = _arg[0];                                                                     \
      this->name[1] = _arg[1];                                                                     \
      this->Modified();                                                                            \
    }                                                                                              \
  }                                                                                                \
  virtual void Set##name(const type _arg[2]) { this->Set##name(_arg[0], _arg[1]); }

/// The time-critical rendering properties of VTK's volume ray casters
/// (vtkFixedPointVolumeRayCastMapper, vtkUnstructuredGridVolumeZSweepMapper), declared the same
/// way in each RayMappers mapper that has them (vtkRayMapperCore::BeginFrame reads them):
///   ImageSampleDistance (1 to 16, default 1): the distance between rays in pixels while
///     AutoAdjustSampleDistances is off (1: one ray per pixel, the exact image);
///   AutoAdjustSampleDistances (default on): interactive renders choose the distance from the
///     last frame's time against the budget, within [MinimumImageSampleDistance,
///     MaximumImageSampleDistance]; still renders use MinimumImageSampleDistance (default 1);
///   FrameBudget (seconds, default 0: 1 / the render window's DesiredUpdateRate);
///   GetLastFrame / SetLastFrame: {time in seconds, sample distance} of the last frame, which
///     the next interactive render scales from. Processes drawing parts of one view set it
///     to the slowest one's before each render (ParaView's representations do), so that
///     all of them draw at one distance and the composited image has no seams between them.
/// The mapper declares the members (and the default of MaximumImageSampleDistance) and
/// defines GetLastFrame / SetLastFrame (vtkRayMapperCore's).
#define vtkRayMapperSampleDistanceMacro()                                                         \
  vtkRayMapperSetClampMacro(ImageSampleDistance, double, 1.0, 16.0);                               \
  vtkGetMacro(ImageSampleDistance, double);                                                        \
  vtkSetMacro(AutoAdjustSampleDistances, vtkTypeBool);                                             \
  vtkGetMacro(AutoAdjustSampleDistances, vtkTypeBool);                                             \
  vtkBooleanMacro(AutoAdjustSampleDistances, vtkTypeBool);                                         \
  vtkRayMapperSetClampMacro(MinimumImageSampleDistance, double, 1.0, 16.0);                        \
  vtkGetMacro(MinimumImageSampleDistance, double);                                                 \
  vtkRayMapperSetClampMacro(MaximumImageSampleDistance, double, 1.0, 16.0);                        \
  vtkGetMacro(MaximumImageSampleDistance, double);                                                 \
  vtkRayMapperSetClampMacro(FrameBudget, double, 0.0, VTK_DOUBLE_MAX);                             \
  vtkGetMacro(FrameBudget, double);                                                                \
  void GetLastFrame(double frame[2]);                                                              \
  void SetLastFrame(const double frame[2])

/// NumberOfThreads of a RayMappers mapper (0 to 4096): its kernels and builds run in its own
/// TBB task arena of that many threads; 0 (default): all the cores, or under MPI the ranks'
/// share of them on this machine; the environment variable RAYMAPPERS_THREADS overrides the
/// default (vtkRayMapperCore::DefaultNumberOfThreads). The mapper declares the member.
#define vtkRayMapperNumberOfThreadsMacro()                                                        \
  vtkRayMapperSetClampMacro(NumberOfThreads, int, 0, 4096);                                        \
  vtkGetMacro(NumberOfThreads, int)

/// LengthUnit of vtkSPHFluidMapper and vtkSPHVoxelizer: the unit of their lengths, the
/// particles' mean radius (PARTICLE_RADIUS) or the input's own unit (WORLD). The class
/// declares the member and its default.
#define vtkRayMapperLengthUnitMacro()                                                             \
  enum LengthUnits                                                                                 \
  {                                                                                                \
    WORLD = 0,                                                                                     \
    PARTICLE_RADIUS = 1                                                                            \
  };                                                                                               \
  vtkSetClampMacro(LengthUnit, int, WORLD, PARTICLE_RADIUS);                                       \
  vtkGetMacro(LengthUnit, int);                                                                    \
  void SetLengthUnitToWorld() { this->SetLengthUnit(WORLD); }                                      \
  void SetLengthUnitToParticleRadius() { this->SetLengthUnit(PARTICLE_RADIUS); }

/// @deprecated The old Subsampling p of vtkZSweepVolumeMapper and vtkSPHFluidMapper (0 to
/// maxP), kept for one release: 0 is AutoAdjustSampleDistances on, p > 0 a fixed
/// ImageSampleDistance p with AutoAdjustSampleDistances off.
#define vtkRayMapperDeprecatedSubsamplingMacro(maxP)                                              \
  virtual void SetSubsampling(int _arg)                                                            \
  {                                                                                                \
    if (vtkRayMapperSetGet::Accept<int>(this, "Subsampling", _arg, 0, maxP, this->GetSubsampling())) \
    {                                                                                              \
      this->SetAutoAdjustSampleDistances(_arg == 0);                                               \
      if (_arg > 0)                                                                                \
      {                                                                                            \
        this->SetImageSampleDistance(_arg);                                                        \
      }                                                                                            \
    }                                                                                              \
  }                                                                                                \
  virtual int GetSubsampling()                                                                     \
  {                                                                                                \
    return this->AutoAdjustSampleDistances ? 0 : static_cast<int>(std::lround(this->ImageSampleDistance)); \
  }

/// @deprecated A numeric property's old name, kept for one release: Set<oldName> checks the
/// value as the old setter did (its warnings name the old property) and forwards it to
/// Set<newName>; Get<oldName> reads <newName>.
#define vtkRayMapperDeprecatedClampAliasMacro(oldName, newName, type, min, max)                   \
  virtual void Set##oldName(type _arg)                                                             \
  {                                                                                                \
    if (vtkRayMapperSetGet::Accept<type>(this, #oldName, _arg, min, max, this->Get##oldName()))    \
    {                                                                                              \
      this->Set##newName(_arg);                                                                    \
    }                                                                                              \
  }                                                                                                \
  virtual type Get##oldName() { return this->Get##newName(); }

/// @deprecated A string property's old name, kept for one release (forwards to <newName>).
#define vtkRayMapperDeprecatedStringAliasMacro(oldName, newName)                                  \
  virtual void Set##oldName(const char* _arg) { this->Set##newName(_arg); }                        \
  virtual char* Get##oldName() { return this->Get##newName(); }

/// ScaleArray (the point array of the particles' sizes, its first component) and ScaleFactor
/// (a factor on every size, 0 to 1e15), vtkPointGaussianMapper's names, declared the same way
/// in each particle mapper (which declares the members).
#define vtkRayMapperScaleMacro()                                                                  \
  vtkSetStringMacro(ScaleArray);                                                                   \
  vtkGetStringMacro(ScaleArray);                                                                   \
  vtkRayMapperSetClampMacro(ScaleFactor, double, 0.0, VTK_RAYMAPPER_LENGTH_MAX);                   \
  vtkGetMacro(ScaleFactor, double)

/// @deprecated RadiusArrayName and RadiusScale, the old names of ScaleArray and ScaleFactor
/// of the sphere, RBF and fluid mappers, kept for one release.
#define vtkRayMapperDeprecatedRadiusNamesMacro()                                                  \
  vtkRayMapperDeprecatedStringAliasMacro(RadiusArrayName, ScaleArray);                             \
  vtkRayMapperDeprecatedClampAliasMacro(RadiusScale, ScaleFactor, double, 0.0, VTK_RAYMAPPER_LENGTH_MAX)

#endif
