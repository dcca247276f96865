// The VTK names of the mappers' properties and their deprecated aliases (issue 28):
//  - ScaleArray / ScaleFactor (vtkPointGaussianMapper's names) of the four particle mappers,
//    and the old names (RadiusArrayName / RadiusScale, SmoothingLengthArrayName /
//    SmoothingLengthScale) reading and writing the same property, the old setter still
//    checking the value (a clamped -1);
//  - the time-critical names of VTK's volume ray casters, and the old Subsampling (ZSweep,
//    fluid) and MaximumReduction (SPH volume) mapped onto them.
#include "vtkCGTSphereMapper.h"
#include "vtkRBFVolumeMapper.h"
#include "vtkSPHFluidMapper.h"
#include "vtkSPHVolumeMapper.h"
#include "vtkZSweepVolumeMapper.h"

#include "vtkNew.h"

#include <cstdio>
#include <cstdlib>
#include <string>

namespace
{
bool ok = true;
void check(bool condition, const char* what)
{
  std::printf("%s %s\n", condition ? "ok  " : "FAIL", what);
  ok = ok && condition;
}

// Old and new radius names on one mapper: the same two properties.
template <typename Mapper, typename SetOldArray, typename GetOldArray, typename SetOldFactor,
  typename GetOldFactor>
void CheckScaleNames(const char* name, SetOldArray setOldArray, GetOldArray getOldArray,
  SetOldFactor setOldFactor, GetOldFactor getOldFactor)
{
  vtkNew<Mapper> m;
  m->SetScaleArray("r");
  const std::string viaOld = getOldArray(m.Get()) ? getOldArray(m.Get()) : "";
  setOldArray(m.Get(), "radius");
  const std::string viaNew = m->GetScaleArray() ? m->GetScaleArray() : "";
  m->SetScaleFactor(2.5);
  const double factorViaOld = getOldFactor(m.Get());
  setOldFactor(m.Get(), 0.5);
  const double factorViaNew = m->GetScaleFactor();
  setOldFactor(m.Get(), -1.0); // clamped to 0 by the old setter's check
  const std::string what = std::string(name) + ": ScaleArray and ScaleFactor, the old names alias them";
  check(viaOld == "r" && viaNew == "radius" && factorViaOld == 2.5 && factorViaNew == 0.5 &&
      m->GetScaleFactor() == 0.0,
    what.c_str());
}

// The old Subsampling p of ZSweep and the fluid on the time-critical properties.
template <typename Mapper>
void CheckSubsampling(const char* name, double maximum)
{
  vtkNew<Mapper> m;
  const bool defaults = m->GetAutoAdjustSampleDistances() && m->GetImageSampleDistance() == 1.0 &&
    m->GetMinimumImageSampleDistance() == 1.0 && m->GetMaximumImageSampleDistance() == maximum &&
    m->GetSubsampling() == 0;
  m->SetSubsampling(3);
  const bool fixed = !m->GetAutoAdjustSampleDistances() && m->GetImageSampleDistance() == 3.0 &&
    m->GetSubsampling() == 3;
  m->SetSubsampling(0);
  const bool automatic = m->GetAutoAdjustSampleDistances() && m->GetSubsampling() == 0;
  const std::string what = std::string(name) +
    ": defaults, Subsampling p = ImageSampleDistance p without auto adjustment, 0 = auto";
  check(defaults && fixed && automatic, what.c_str());
}
}

int TestRayMapperProperties(int, char*[])
{
  CheckScaleNames<vtkCGTSphereMapper>("vtkCGTSphereMapper",
    [](vtkCGTSphereMapper* m, const char* s) { m->SetRadiusArrayName(s); },
    [](vtkCGTSphereMapper* m) { return m->GetRadiusArrayName(); },
    [](vtkCGTSphereMapper* m, double v) { m->SetRadiusScale(v); },
    [](vtkCGTSphereMapper* m) { return m->GetRadiusScale(); });
  CheckScaleNames<vtkRBFVolumeMapper>("vtkRBFVolumeMapper",
    [](vtkRBFVolumeMapper* m, const char* s) { m->SetRadiusArrayName(s); },
    [](vtkRBFVolumeMapper* m) { return m->GetRadiusArrayName(); },
    [](vtkRBFVolumeMapper* m, double v) { m->SetRadiusScale(v); },
    [](vtkRBFVolumeMapper* m) { return m->GetRadiusScale(); });
  CheckScaleNames<vtkSPHFluidMapper>("vtkSPHFluidMapper",
    [](vtkSPHFluidMapper* m, const char* s) { m->SetRadiusArrayName(s); },
    [](vtkSPHFluidMapper* m) { return m->GetRadiusArrayName(); },
    [](vtkSPHFluidMapper* m, double v) { m->SetRadiusScale(v); },
    [](vtkSPHFluidMapper* m) { return m->GetRadiusScale(); });
  CheckScaleNames<vtkSPHVolumeMapper>("vtkSPHVolumeMapper",
    [](vtkSPHVolumeMapper* m, const char* s) { m->SetSmoothingLengthArrayName(s); },
    [](vtkSPHVolumeMapper* m) { return m->GetSmoothingLengthArrayName(); },
    [](vtkSPHVolumeMapper* m, double v) { m->SetSmoothingLengthScale(v); },
    [](vtkSPHVolumeMapper* m) { return m->GetSmoothingLengthScale(); });

  CheckSubsampling<vtkZSweepVolumeMapper>("vtkZSweepVolumeMapper", 9.0);
  CheckSubsampling<vtkSPHFluidMapper>("vtkSPHFluidMapper", 8.0);
  vtkNew<vtkSPHVolumeMapper> sph;
  const bool sphDefault = sph->GetMaximumImageSampleDistance() == 4.0 && sph->GetMaximumReduction() == 4.0;
  sph->SetMaximumReduction(2.5);
  check(sphDefault && sph->GetMaximumImageSampleDistance() == 2.5,
    "vtkSPHVolumeMapper: MaximumReduction aliases MaximumImageSampleDistance (default 4)");
  return ok ? EXIT_SUCCESS : EXIT_FAILURE;
}
