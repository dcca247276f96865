/**
 * @class   vtkSPHVolumeMapper
 * @brief   Volume renders SPH particles directly, as the SPH field of their quantity.
 *
 * Every point i of the input vtkPointSet (cells are ignored) is an SPH particle with the
 * quantity Q_i, the volume V_i and the smoothing length h_i; the mapper ray casts the field
 *   Q(x) = sum_i Q_i V_i W(|x - x_i|, H_i) / sum_i V_i W(|x - x_i|, H_i)
 * (Limper 2012, equation 2.4) with the vtkVolumeProperty of the vtkVolume (colour and scalar
 * opacity of component 0, opacity per ScalarOpacityUnitDistance corrected for the adaptive
 * step; Shade turns on Blinn-Phong lighting with the field's exact gradient), through a
 * perspective grid over the view frustum rebuilt every frame (Limper 2012, chapter 3).
 *   Q_i: ValueArrayName (first component), else the active point scalars, else 1.
 *   V_i: VolumeArrayName; else MassArrayName / DensityArrayName; else the constant Volume.
 *   h_i: ScaleFactor * (ScaleArray, else SmoothingLength); the
 *        kernel's support is H_i = SupportFactor * h_i (SupportFactor 0: the kernel's own
 *        convention, h for poly6 and 2h for the cubic spline and Wendland C2).
 *        SmoothingLength 0 (the default) is automatic: the support H = 2.4 s, s the typical
 *        particle spacing (the median nearest-neighbour distance on a sample:
 *        vtkRayMapperParticleSizes), i.e. h = 1.2 s for the cubic spline, the ratio SPH
 *        codes run with (about 58 neighbours inside the support on a lattice), so the
 *        normalized field is smooth and follows the data's units, not its bounds.
 *
 * Normalization: NORMALIZED (equation 3.14, default), UNNORMALIZED (3.15) or
 * PSEUDO_NORMALIZED (3.16, divided by ReferenceWeightSum; 0 chooses 12 neighbours at half
 * the median support with the median volume). ContourShading adds ContourColor with
 * ContourOpacity where the sum of weights falls below ReferenceWeightSum (3.24 to 3.26).
 * StepFactor scales the step (1: a pixel's footprint); SamplesPerSupport (default 8) keeps it
 * at least the smallest kernel support over that many steps, so near the eye and at high
 * resolutions the step follows the field's detail rather than the pixels (0: the thesis's
 * pixel-tied steps alone; where those are longer, they are taken).
 * TileSize is the grid's cell size in
 * pixels and the ray bundle's side, SlabDepth the samples per slab (0: a cell's),
 * TerminationOpacity the early ray termination, Jitter stochastic jittering.
 *
 * Interaction (section 3.1): while the render window asks for at least one frame per
 * second (an interactor's DesiredUpdateRate during camera moves), the image and the steps
 * are reduced by a factor r, the image sample distance of VTK's volume ray casters: with
 * AutoAdjustSampleDistances (default) chosen from the last frame's time against FrameBudget
 * (0: 1 / DesiredUpdateRate) within [MinimumImageSampleDistance 1,
 * MaximumImageSampleDistance 4]; a still render uses the minimum (vtkRayMapperSetGet.h).
 *
 * Opaque geometry already drawn stops the rays (the depth buffer is read only when the
 * renderer holds some: effect opaque_depth). Bad input never poisons the image:
 * particles with NaN/Inf coordinates, quantities or volumes (or beyond float), supports
 * that are NaN, infinite, zero, negative or above 1e15, and negative volumes are skipped
 * with one warning saying how many; missing arrays fall back as above with a warning.
 * Numeric properties reject NaN and infinity and clamp out-of-range values, each with one
 * warning (vtkRayMapperSetGet.h; lengths up to 1e15); an array of several components read
 * as a scalar gives its first component (one warning when they differ); a degenerate camera
 * (the eye at the focal point, a NaN position) gives one warning and nothing drawn.
 *
 * GetStatistics() reports phase times, counters and effects of the last render.
 */
#ifndef vtkSPHVolumeMapper_h
#define vtkSPHVolumeMapper_h

#include "RayMappersMappersModule.h" // for export macro
#include "vtkRayMapperParticleVolumeMapper.h"
#include "vtkRayMapperSetGet.h" // for vtkRayMapperSetClampMacro

#include <memory> // for std::unique_ptr

class vtkPointSet;
struct vtkRayMapperView;
namespace raymappers
{
struct SPHRenderParameters;
}

#define VTK_SPH_KERNEL_POLY6 0
#define VTK_SPH_KERNEL_CUBIC_SPLINE 1
#define VTK_SPH_KERNEL_WENDLAND_C2 2

#define VTK_SPH_NORMALIZED 0
#define VTK_SPH_UNNORMALIZED 1
#define VTK_SPH_PSEUDO_NORMALIZED 2

class RAYMAPPERSMAPPERS_EXPORT vtkSPHVolumeMapper : public vtkRayMapperParticleVolumeMapper
{
public:
  static vtkSPHVolumeMapper* New();
  vtkTypeMacro(vtkSPHVolumeMapper, vtkRayMapperParticleVolumeMapper);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /** The smoothing kernel (default VTK_SPH_KERNEL_CUBIC_SPLINE). */
  vtkRayMapperSetClampMacro(Kernel, int, VTK_SPH_KERNEL_POLY6, VTK_SPH_KERNEL_WENDLAND_C2);
  vtkGetMacro(Kernel, int);
  ///@}

  ///@{
  /** Support radius per smoothing length; 0 (default): the kernel's convention. */
  vtkRayMapperSetClampMacro(SupportFactor, double, 0.0, 100.0);
  vtkGetMacro(SupportFactor, double);
  /**
   * The support radius per smoothing length, H_i / h_i: SupportFactor when it is positive,
   * else the Kernel's own convention (1 for poly6, whose h is its support; 2 for the cubic
   * spline and Wendland C2).
   */
  double GetSupportPerSmoothingLength();
  ///@}

  ///@{
  /** Constant smoothing length (default 0: automatic, GetAutomaticSupportPerSpacing() = 2.4
   * spacings of support; 1% of the bounds' diagonal without a spacing), its array ScaleArray,
   * and a factor ScaleFactor on either (1; vtkPointGaussianMapper's names). */
  vtkRayMapperSetClampMacro(SmoothingLength, double, 0.0, VTK_RAYMAPPER_LENGTH_MAX);
  vtkGetMacro(SmoothingLength, double);
  static double GetAutomaticSupportPerSpacing()
  {
    return vtkRayMapperParticleSizes::SPHSupportPerSpacing;
  }
  ///@}

  /** The constant smoothing length in use for the current input: SmoothingLength, or the
   * automatic one when it is 0 (before ScaleFactor). */
  double GetSmoothingLengthInUse();

  ///@{
  /** @deprecated SmoothingLengthArrayName and SmoothingLengthScale, the old names of
   * ScaleArray and ScaleFactor (those of vtkPointGaussianMapper), kept for one release. */
  vtkRayMapperDeprecatedStringAliasMacro(SmoothingLengthArrayName, ScaleArray);
  vtkRayMapperDeprecatedClampAliasMacro(
    SmoothingLengthScale, ScaleFactor, double, 0.0, VTK_RAYMAPPER_LENGTH_MAX);
  ///@}

  ///@{
  /** The quantity Q shown (default: the active point scalars, else 1). */
  vtkSetStringMacro(ValueArrayName);
  vtkGetStringMacro(ValueArrayName);
  ///@}

  ///@{
  /**
   * The particle volume: an array of V, or arrays of mass and density (V = m / rho), or
   * the constant Volume (default 1).
   */
  vtkSetStringMacro(VolumeArrayName);
  vtkGetStringMacro(VolumeArrayName);
  vtkSetStringMacro(MassArrayName);
  vtkGetStringMacro(MassArrayName);
  vtkSetStringMacro(DensityArrayName);
  vtkGetStringMacro(DensityArrayName);
  vtkRayMapperSetClampMacro(Volume, double, 0.0, VTK_RAYMAPPER_LENGTH_MAX);
  vtkGetMacro(Volume, double);
  ///@}

  ///@{
  /** VTK_SPH_NORMALIZED (default), VTK_SPH_UNNORMALIZED or VTK_SPH_PSEUDO_NORMALIZED. */
  vtkRayMapperSetClampMacro(Normalization, int, VTK_SPH_NORMALIZED, VTK_SPH_PSEUDO_NORMALIZED);
  vtkGetMacro(Normalization, int);
  ///@}

  ///@{
  /** w_max of equation 3.16; 0 (default): computed from the particles. */
  vtkRayMapperSetClampMacro(ReferenceWeightSum, double, 0.0, VTK_RAYMAPPER_LENGTH_MAX);
  vtkGetMacro(ReferenceWeightSum, double);
  ///@}

  ///@{
  /** Contour shading (default off), its colour (black) and opacity per unit distance (0.5). */
  vtkSetMacro(ContourShading, bool);
  vtkGetMacro(ContourShading, bool);
  vtkBooleanMacro(ContourShading, bool);
  vtkRayMapperSetVector3ClampMacro(ContourColor, double, 0.0, 1.0);
  vtkGetVector3Macro(ContourColor, double);
  vtkRayMapperSetClampMacro(ContourOpacity, double, 0.0, 1.0);
  vtkGetMacro(ContourOpacity, double);
  ///@}

  ///@{
  /** Step relative to a pixel's footprint (default 1), steps per smallest support that
   * bound it (8; 0: no bound), grid tile (16 pixels), slab depth
   * (0: a cell's samples), early termination opacity (0.99; 1: never), jitter (off). */
  vtkRayMapperSetClampMacro(StepFactor, double, 0.05, 64.0);
  vtkGetMacro(StepFactor, double);
  vtkRayMapperSetClampMacro(SamplesPerSupport, double, 0.0, 1024.0);
  vtkGetMacro(SamplesPerSupport, double);
  vtkRayMapperSetClampMacro(TileSize, int, 2, 64);
  vtkGetMacro(TileSize, int);
  vtkRayMapperSetClampMacro(SlabDepth, int, 0, 1024);
  vtkGetMacro(SlabDepth, int);
  vtkRayMapperSetClampMacro(TerminationOpacity, double, 0.0, 1.0);
  vtkGetMacro(TerminationOpacity, double);
  vtkSetMacro(Jitter, bool);
  vtkGetMacro(Jitter, bool);
  vtkBooleanMacro(Jitter, bool);
  ///@}

  ///@{
  /** Interactive sampling reduction (equation 3.1) r = the image sample distance: see
   * vtkRayMapperSampleDistanceMacro (vtkRayMapperSetGet.h). */
  vtkRayMapperSampleDistanceMacro();
  ///@}

  ///@{
  /** @deprecated MaximumReduction, the old name of MaximumImageSampleDistance, kept for one
   * release. */
  vtkRayMapperDeprecatedClampAliasMacro(
    MaximumReduction, MaximumImageSampleDistance, double, 1.0, 16.0);
  ///@}

  ///@{
  /**
   * The box the samples are restricted to (xmin, xmax, ymin, ymax, zmin, zmax in model
   * coordinates; default: all of space). Distributed rendering sets it to the process's
   * region of the partition (its particles plus the ghosts whose support reaches in), so
   * that the regions' images composite front to back to the one-process image.
   */
  vtkSetVector6Macro(RegionBounds, double);
  vtkGetVector6Macro(RegionBounds, double);
  ///@}

  ///@{
  /**
   * The support SamplesPerSupport divides (> 0), instead of the smallest support of the
   * particles drawn (0, the default). Distributed rendering sets it to the smallest of all
   * processes' (GetParticlesSmallestSupport on each, reduced), so that every process steps
   * alike: the sample depths lie on a lattice set by the camera alone, and the processes'
   * images then blend to the one-process image.
   */
  vtkRayMapperSetClampMacro(SmallestSupport, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(SmallestSupport, double);
  ///@}

  ///@{
  /**
   * The point the particles' coordinates are stored relative to, in float (the kernels'
   * precision), when UseFloatOrigin is on; off (the default): the centre of their finite
   * bounds. Distributed rendering sets the centre of all processes' bounds on each, so that
   * a particle, and the field at a sample, is rounded alike on every process.
   */
  vtkRayMapperSetVector3ClampMacro(FloatOrigin, double, -VTK_DOUBLE_MAX, VTK_DOUBLE_MAX);
  vtkGetVector3Macro(FloatOrigin, double);
  vtkSetMacro(UseFloatOrigin, bool);
  vtkGetMacro(UseFloatOrigin, bool);
  vtkBooleanMacro(UseFloatOrigin, bool);
  ///@}

  /**
   * The smallest kernel support of the particles of `input` that are drawn (0 when none
   * is), from the particles built for it (built now if they changed, as a render would).
   */
  double GetParticlesSmallestSupport(vtkPointSet* input);

protected:
  vtkSPHVolumeMapper();
  ~vtkSPHVolumeMapper() override;

  /// The largest support of a particle (the bounds' growth).
  double GetSupportRadius(vtkPointSet* input) override;
  /// One render, in the mapper's task arena (Render runs it there).
  void RenderVolume(vtkRenderer* ren, vtkVolume* vol, vtkPointSet* input) override;
  void ReleaseBuilds() override;

  int Kernel = VTK_SPH_KERNEL_CUBIC_SPLINE;
  double SupportFactor = 0.0;
  double SmoothingLength = 0.0;
  char* ValueArrayName = nullptr;
  char* VolumeArrayName = nullptr;
  char* MassArrayName = nullptr;
  char* DensityArrayName = nullptr;
  double Volume = 1.0;
  int Normalization = VTK_SPH_NORMALIZED;
  double ReferenceWeightSum = 0.0;
  bool ContourShading = false;
  double ContourColor[3] = { 0, 0, 0 };
  double ContourOpacity = 0.5;
  double StepFactor = 1.0;
  double SamplesPerSupport = 8.0;
  double SmallestSupport = 0.0;
  double FloatOrigin[3] = { 0, 0, 0 };
  bool UseFloatOrigin = false;
  int TileSize = 16;
  int SlabDepth = 0;
  double TerminationOpacity = 0.99;
  bool Jitter = false;
  double ImageSampleDistance = 1.0;
  vtkTypeBool AutoAdjustSampleDistances = 1;
  double MinimumImageSampleDistance = 1.0;
  double MaximumImageSampleDistance = 4.0;
  double FrameBudget = 0.0;
  double RegionBounds[6] = { -VTK_DOUBLE_MAX, VTK_DOUBLE_MAX, -VTK_DOUBLE_MAX, VTK_DOUBLE_MAX,
    -VTK_DOUBLE_MAX, VTK_DOUBLE_MAX };

private:
  vtkSPHVolumeMapper(const vtkSPHVolumeMapper&) = delete;
  void operator=(const vtkSPHVolumeMapper&) = delete;

  /// Rebuilds the particles when the input, the arrays or the particle settings changed.
  void UpdateParticles(vtkPointSet* input);
  /// The kernel's parameters: the properties, the model transform, lights and material.
  raymappers::SPHRenderParameters GatherParameters(vtkRenderer* ren,
    vtkVolume* vol,
    const vtkRayMapperView& view);

  struct Internals;
  std::unique_ptr<Internals> Impl;
};

#endif
