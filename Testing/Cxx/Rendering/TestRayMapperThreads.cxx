// NumberOfThreads (vtkRayMapperCore::Execute): a mapper's builds and kernel run in its own
// task arena of that many threads. For the sphere mapper and the RBF volume mapper, each
// setting rebuilds (the points marked modified) and renders: the counter "threads" (the
// arena's concurrency seen inside it) is the setting, 0 gives the default
// (vtkRayMapperCore::DefaultNumberOfThreads), and the picture is the same byte for byte.
#include "RenderingTestHelpers.h"
#include "vtkCGTSphereMapper.h"
#include "vtkRBFVolumeMapper.h"
#include "vtkRayMapperCore.h"
#include "vtkRayMapperStatistics.h"

#include "vtkActor.h"
#include "vtkColorTransferFunction.h"
#include "vtkPiecewiseFunction.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"

#include <cstdio>

namespace
{
bool ok = true;
void check(bool condition, const char* what)
{
  std::printf("%s %s\n", condition ? "ok  " : "FAIL", what);
  ok = ok && condition;
}

// Renders after a rebuild at each thread count; the counter and the picture of each.
template <typename Mapper>
void CheckThreads(const char* name, Mapper* mapper, vtkPolyData* points, vtkRenderWindow* win)
{
  std::vector<unsigned char> first;
  for (const int n : { 1, 2, 3, 0 })
  {
    mapper->SetNumberOfThreads(n);
    points->Modified();
    win->Render();
    const auto image = rmtest::ReadRGB(win);
    const long long threads = mapper->GetStatistics()->GetCounter("threads");
    const int expected = n > 0 ? n : vtkRayMapperCore::DefaultNumberOfThreads();
    std::printf("%s, NumberOfThreads %d: %lld threads\n", name, n, threads);
    check(threads == expected, "the kernel ran in an arena of NumberOfThreads threads");
    if (first.empty())
    {
      // Something drawn: a pixel unlike the corner's background.
      bool drawn = false;
      for (std::size_t i = 0; i + 2 < image.size(); i += 3)
      {
        drawn = drawn || image[i] != image[0] || image[i + 1] != image[1] || image[i + 2] != image[2];
      }
      check(drawn, "the picture shows the data");
      first = image;
    }
    check(image == first, "the same picture as with one thread");
  }
}
}

int TestRayMapperThreads(int, char*[])
{
  auto lattice = rmtest::MakeLattice(6);
  vtkNew<vtkCGTSphereMapper> spheres;
  spheres->SetInputData(lattice);
  spheres->SetScaleArray("radius");
  vtkNew<vtkActor> actor;
  actor->SetMapper(spheres);
  vtkNew<vtkRenderer> ren;
  ren->AddActor(actor);
  vtkNew<vtkRenderWindow> win;
  win->SetSize(160, 120);
  win->AddRenderer(ren);
  ren->ResetCamera();
  CheckThreads("vtkCGTSphereMapper", spheres.Get(), lattice, win);
  ren->RemoveActor(actor);

  vtkNew<vtkRBFVolumeMapper> rbf;
  rbf->SetInputData(lattice);
  rbf->SetScaleArray("radius");
  vtkNew<vtkColorTransferFunction> color;
  color->AddRGBPoint(0.0, 0.2, 0.3, 1.0);
  color->AddRGBPoint(1.0, 1.0, 0.8, 0.2);
  vtkNew<vtkPiecewiseFunction> opacity;
  opacity->AddPoint(0.0, 0.0);
  opacity->AddPoint(1.0, 0.8);
  vtkNew<vtkVolume> volume;
  volume->SetMapper(rbf);
  volume->GetProperty()->SetColor(color);
  volume->GetProperty()->SetScalarOpacity(opacity);
  ren->AddVolume(volume);
  ren->ResetCamera();
  CheckThreads("vtkRBFVolumeMapper", rbf.Get(), lattice, win);
  return ok ? EXIT_SUCCESS : EXIT_FAILURE;
}
