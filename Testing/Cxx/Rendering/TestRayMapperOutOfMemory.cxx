// Every mapper given an input whose structures do not fit in the memory left to it: the
// process's address space (RLIMIT_AS) lowered to what it has mapped plus 32 MiB, then an
// input of about two million particles or a million tetrahedra rendered (its structures
// take 80 MB and more) and read back (vtkWindowToImageFilter renders once more). Each mapper
// must report exactly one error naming "Out of memory" over both renders, set the counter
// out_of_memory to 1, draw nothing (the background) and not crash; with the
// limit lifted, the same input rendered again must be built anew and drawn, silently (what
// the failed build left is released and its stamps invalidated: a stale stamp draws
// nothing). The filter vtkSPHVoxelizer likewise: one error, an empty output, then the spans.
// Under AddressSanitizer, whose allocator aborts instead of throwing, it is skipped
// (exit 125).
#include "BadInputViewer.h"
#include "RenderingTestHelpers.h"
#include "vtkCGTSphereMapper.h"
#include "vtkRBFVolumeMapper.h"
#include "vtkSPHFluidMapper.h"
#include "vtkSPHVoxelizer.h"
#include "vtkSPHVolumeMapper.h"
#include "vtkZSweepVolumeMapper.h"

#include "vtkActor.h"
#include "vtkColorTransferFunction.h"
#include "vtkDataSetTriangleFilter.h"
#include "vtkExtractVOI.h"
#include "vtkImageData.h"
#include "vtkPiecewiseFunction.h"
#include "vtkRTAnalyticSource.h"
#include "vtkUnstructuredGrid.h"

#include <sys/resource.h>

#include <fstream>
#include <functional>
#include <string>

namespace
{
using raymappers::test::RGBImage;

constexpr long long Margin = 32ll << 20; // bytes of address space left above what is mapped

/// The process's mapped address space (VmSize of /proc/self/status), in bytes.
long long MappedBytes()
{
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line))
  {
    if (line.rfind("VmSize:", 0) == 0)
    {
      return std::stoll(line.substr(7)) * 1024;
    }
  }
  return -1;
}

/// The number of pixels that are not black (the windows' background).
std::size_t Lit(const RGBImage& image)
{
  std::size_t n = 0;
  for (std::size_t k = 0; k + 2 < image.rgb.size(); k += 3)
  {
    n += image.rgb[k] + image.rgb[k + 1] + image.rgb[k + 2] > 0;
  }
  return n;
}

/// The check of one mapper: `show(data)` sets the input and renders. A small input first
/// (the threads, the window and the drawer made), then `big` under the lowered limit, then
/// `big` again with the limit lifted.
template <typename Viewer, typename Data>
bool CheckMapper(const char* name, Viewer& v, Data* small, Data* big)
{
  std::printf("== %s\n", name);
  auto& log = v.Log;
  log.Check(Lit(v.Show(small)) > 0, std::string(name) + ": the small input is drawn");
  log.Silent(std::string(name) + ": the small input");
  rlimit old{};
  getrlimit(RLIMIT_AS, &old);
  rlimit low = old;
  low.rlim_cur = static_cast<rlim_t>(MappedBytes() + Margin);
  log.Check(setrlimit(RLIMIT_AS, &low) == 0, "the address space limited");
  const RGBImage starved = v.Show(big);
  setrlimit(RLIMIT_AS, &old);
  log.Errored(1, "Out of memory", std::string(name) + ": one error under the limit");
  log.Check(v.Mapper->GetStatistics()->GetCounter("out_of_memory") == 1,
    std::string(name) + ": counter out_of_memory = 1");
  log.Check(Lit(starved) == 0, std::string(name) + ": nothing drawn under the limit");
  const RGBImage fed = v.Render();
  log.Silent(std::string(name) + ": the limit lifted");
  log.Check(v.Mapper->GetStatistics()->GetCounter("out_of_memory") == 0,
    std::string(name) + ": counter out_of_memory = 0 after");
  log.Check(Lit(fed) > 0, std::string(name) + ": the same input built again and drawn");
  return log.Ok;
}

/// A lattice of n^3 particles in [-1, 1]^3 with the SPH arrays h (the spacing), m and rho.
vtkSmartPointer<vtkPolyData> Particles(int n)
{
  auto data = rmtest::MakeLattice(n);
  for (const char* name : { "h", "m", "rho" })
  {
    vtkNew<vtkDoubleArray> a;
    a->SetName(name);
    a->SetNumberOfTuples(data->GetNumberOfPoints());
    a->Fill(name[0] == 'h' ? 2.0 / (n - 1) : 1.0);
    data->GetPointData()->AddArray(a);
  }
  return data;
}

/// The wavelet on [-30, 30]^3, every `rate`-th point, its voxels split into 5 tetrahedra
/// each (RTData in 37..277).
vtkSmartPointer<vtkUnstructuredGrid> Tetrahedra(int rate)
{
  vtkNew<vtkRTAnalyticSource> wavelet;
  wavelet->SetWholeExtent(-30, 30, -30, 30, -30, 30);
  vtkNew<vtkExtractVOI> every;
  every->SetInputConnection(wavelet->GetOutputPort());
  every->SetVOI(-30, 30, -30, 30, -30, 30);
  every->SetSampleRate(rate, rate, rate);
  vtkNew<vtkDataSetTriangleFilter> tetrahedralize;
  tetrahedralize->SetInputConnection(every->GetOutputPort());
  tetrahedralize->Update();
  auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
  grid->ShallowCopy(tetrahedralize->GetOutput());
  return grid;
}

/// The filter's door: vtkSPHVoxelizer on `big` under the lowered limit gives one error naming
/// "Out of memory" and an empty output, then with the limit lifted the spans, silently.
bool CheckVoxelizer(vtkPolyData* big)
{
  std::printf("== vtkSPHVoxelizer\n");
  vtkNew<vtkSPHVoxelizer> voxelizer;
  voxelizer->SetImageSize(96, 96);
  voxelizer->SetInputData(big);
  rmtest::EventCounter events;
  events.Observe(voxelizer);
  rlimit old{};
  getrlimit(RLIMIT_AS, &old);
  rlimit low = old;
  low.rlim_cur = static_cast<rlim_t>(MappedBytes() + Margin);
  setrlimit(RLIMIT_AS, &low);
  voxelizer->Update();
  setrlimit(RLIMIT_AS, &old);
  bool ok = events.Errors == 1 && events.Warnings == 0 &&
    events.Last.find("Out of memory") != std::string::npos;
  ok = ok && voxelizer->GetOutput()->GetNumberOfPoints() == 0;
  std::printf("%s vtkSPHVoxelizer: one error and an empty output under the limit\n",
    ok ? "ok  " : "FAIL");
  voxelizer->Modified();
  voxelizer->Update();
  const bool fed = events.Errors == 1 && events.Warnings == 0 &&
    voxelizer->GetOutput()->GetNumberOfPoints() == 96 * 96;
  std::printf("%s vtkSPHVoxelizer: the limit lifted, the spans silently\n", fed ? "ok  " : "FAIL");
  return ok && fed;
}

template <typename Property>
void Classify(Property* property, double lo, double hi)
{
  vtkNew<vtkColorTransferFunction> color;
  color->AddRGBPoint(lo, 0.2, 0.3, 0.9);
  color->AddRGBPoint(hi, 1.0, 0.8, 0.2);
  vtkNew<vtkPiecewiseFunction> opacity;
  opacity->AddPoint(lo, 0.2);
  opacity->AddPoint(hi, 0.8);
  property->SetColor(color);
  property->SetScalarOpacity(opacity);
}

struct Spheres : rmtest::BadInputViewer<vtkCGTSphereMapper, vtkPolyData>
{
  vtkNew<vtkActor> Actor;
  Spheres()
  {
    Actor->SetMapper(Mapper);
    Ren->AddActor(Actor);
    Open(96, 1, 2, 7);
  }
};

template <typename MapperT, typename DataT>
struct Volume : rmtest::BadInputVolumeViewer<MapperT, DataT>
{
  explicit Volume(double lo = 0, double hi = 30, double eye = 7)
  {
    Classify(this->Property.GetPointer(), lo, hi);
    this->ClipHalfSide = eye / 2;
    this->Open(96, eye / 7, 2 * eye / 7, eye);
  }
};
}

int TestRayMapperOutOfMemory(int, char*[])
{
#if defined(__SANITIZE_ADDRESS__)
  std::printf("skipped: AddressSanitizer's allocator aborts where a failed allocation throws\n");
  return 125;
#else
  bool ok = true;
  auto small = Particles(6);
  auto big = Particles(126); // 2,000,376 particles
  // (First: what a mapper frees stays in the heap, where the filter's arrays would fit.)
  ok = CheckVoxelizer(big.GetPointer()) && ok;
  {
    Spheres v;
    ok = CheckMapper("vtkCGTSphereMapper", v, small.GetPointer(), big.GetPointer()) && ok;
  }
  {
    Volume<vtkRBFVolumeMapper, vtkPolyData> v;
    v.Mapper->SetValueArrayName("value");
    ok = CheckMapper("vtkRBFVolumeMapper", v, small.GetPointer(), big.GetPointer()) && ok;
  }
  {
    Volume<vtkSPHVolumeMapper, vtkPolyData> v;
    v.Mapper->SetValueArrayName("value");
    ok = CheckMapper("vtkSPHVolumeMapper", v, small.GetPointer(), big.GetPointer()) && ok;
  }
  {
    Volume<vtkSPHFluidMapper, vtkPolyData> v;
    ok = CheckMapper("vtkSPHFluidMapper", v, small.GetPointer(), big.GetPointer()) && ok;
  }
  {
    auto cells = Tetrahedra(10);
    auto many = Tetrahedra(1); // 60^3 voxels, 1,080,000 tetrahedra
    Volume<vtkZSweepVolumeMapper, vtkUnstructuredGrid> v(37, 277, 200);
    ok = CheckMapper("vtkZSweepVolumeMapper", v, cells.GetPointer(), many.GetPointer()) && ok;
  }
  std::printf("%s\n", ok ? "PASS" : "FAIL");
  return ok ? 0 : 1;
#endif
}
