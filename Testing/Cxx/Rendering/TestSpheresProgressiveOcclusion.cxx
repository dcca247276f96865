// Progressive ambient occlusion through the VTK mapper (AmbientOcclusionSamplesPerFrame):
// still renders of the same view add the next directions until all are in, and the window
// then shows exactly the one-shot picture; a camera move, a window resize, a property, the
// actor's colour or the data starts again from the first directions.
#include "RenderingTestHelpers.h"
#include "vtkCGTSphereMapper.h"
#include "vtkRayMapperStatistics.h"

#include "vtkActor.h"
#include "vtkLight.h"
#include "vtkLightCollection.h"
#include "vtkPoints.h"
#include "vtkProperty.h"

#include <functional>
#include <random>

int TestSpheresProgressiveOcclusion(int, char*[])
{
  std::vector<std::array<double, 3>> c;
  std::vector<double> r;
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  for (int i = 0; i < 150; ++i)
  {
    c.push_back({ u(rng), u(rng), u(rng) });
    r.push_back(0.3);
  }
  auto data = rmtest::MakeSpheres(c, r);
  vtkNew<vtkCGTSphereMapper> mapper;
  mapper->SetInputData(data);
  mapper->SetRadiusArrayName("radius");
  mapper->ScalarVisibilityOff();
  mapper->SetAmbientOcclusionSamples(16);
  mapper->SetAmbientOcclusionRadius(0.8);
  vtkNew<vtkActor> actor;
  actor->SetMapper(mapper);
  actor->GetProperty()->SetColor(0.9, 0.85, 0.7);
  actor->GetProperty()->SetAmbient(0.15);
  vtkNew<vtkRenderer> ren;
  ren->AddActor(actor);
  vtkNew<vtkRenderWindow> win;
  win->SetSize(200, 160);
  win->AddRenderer(ren);
  vtkCamera* cam = ren->GetActiveCamera();
  cam->SetPosition(1, 3, 8);
  cam->SetFocalPoint(0, 0, 0);
  ren->ResetCameraClippingRange(-3, 3, -3, 3, -3, 3);
  vtkRayMapperStatistics* s = mapper->GetStatistics();
  const auto done = [&] { return s->GetCounter("ao_samples_done"); };

  // The one-shot picture (the default budget 0: all 16 in every render).
  win->Render();
  RM_CHECK(done() == 16 && mapper->GetAmbientOcclusionConverged());
  RM_CHECK(!s->GetEffect("ao_progressive") && s->GetEffect("ao_local_queries"));
  const std::vector<unsigned char> oneShot = rmtest::ReadRGB(win);

  // Budget 5: 5, 10, 15, 16 directions; only the last render is converged, and it shows
  // the one-shot picture; a render after it traces no occlusion ray.
  mapper->SetAmbientOcclusionSamplesPerFrame(5);
  std::vector<unsigned char> first;
  for (const int expected : { 5, 10, 15, 16 })
  {
    win->Render();
    RM_CHECK(done() == expected);
    RM_CHECK(s->GetEffect("ao_progressive"));
    RM_CHECK(mapper->GetAmbientOcclusionConverged() == (expected == 16));
    RM_CHECK(s->GetCounter("ao_rays") == (expected == 16 ? 1 : 5) * s->GetCounter("hits"));
    if (expected == 5)
    {
      first = rmtest::ReadRGB(win);
      RM_CHECK(first != oneShot); // 5 of 16 directions: another share at many pixels
    }
  }
  RM_CHECK(rmtest::ReadRGB(win) == oneShot);
  win->Render();
  RM_CHECK(done() == 16 && s->GetCounter("ao_rays") == 0);
  RM_CHECK(rmtest::ReadRGB(win) == oneShot);

  // Each change restarts: the next render traces directions 0..4 again.
  const std::vector<std::pair<const char*, std::function<void()>>> changes = {
    { "camera", [&] { cam->Azimuth(5); } },
    { "window size", [&] { win->SetSize(180, 160); } },
    { "actor colour", [&] { actor->GetProperty()->SetColor(0.5, 0.85, 0.7); } },
    { "occlusion radius", [&] { mapper->SetAmbientOcclusionRadius(0.6); } },
    { "data", [&] { data->Modified(); } },
    { "light",
      [&] { vtkLight::SafeDownCast(ren->GetLights()->GetItemAsObject(0))->SetIntensity(0.7); } },
  };
  for (const auto& [what, change] : changes)
  {
    win->Render();
    RM_CHECK(done() > 5);
    change();
    win->Render();
    if (done() != 5)
    {
      std::printf("after the change of the %s: %lld directions, not 5\n",
        what,
        static_cast<long long>(done()));
      return EXIT_FAILURE;
    }
  }
  return EXIT_SUCCESS;
}
