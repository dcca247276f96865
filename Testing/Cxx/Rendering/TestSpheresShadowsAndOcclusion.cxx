// Soft shadows from the area light and ambient occlusion through the VTK mapper: a cloud
// of spheres over a large "floor" sphere. Checks that shadows darken the floor under the
// cloud and not elsewhere, that counters show the secondary rays only when asked for, and
// compares the picture with the baseline.
#include "RenderingTestHelpers.h"
#include "vtkCGTSphereMapper.h"
#include "vtkRayMapperStatistics.h"

#include "vtkActor.h"
#include "vtkProperty.h"

#include <random>

int TestSpheresShadowsAndOcclusion(int argc, char* argv[])
{
  std::vector<std::array<double, 3>> c;
  std::vector<double> r;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  for (int i = 0; i < 60; ++i)
  {
    c.push_back({ u(rng), 1.0 + 0.5 * u(rng), u(rng) });
    r.push_back(0.25);
  }
  c.push_back({ 0, -40, 0 }); // the floor: a sphere large enough to look flat
  r.push_back(39.5);
  auto data = rmtest::MakeSpheres(c, r);
  vtkNew<vtkCGTSphereMapper> mapper;
  mapper->SetInputData(data);
  mapper->SetRadiusArrayName("radius");
  mapper->ScalarVisibilityOff();
  vtkNew<vtkActor> actor;
  actor->SetMapper(mapper);
  actor->GetProperty()->SetColor(0.9, 0.85, 0.7);
  actor->GetProperty()->SetAmbient(0.15);
  actor->GetProperty()->SetDiffuse(0.85);
  vtkNew<vtkRenderer> ren;
  ren->AddActor(actor);
  ren->SetBackground(0.2, 0.25, 0.35);
  vtkNew<vtkRenderWindow> win;
  win->SetSize(320, 240);
  win->AddRenderer(ren);
  vtkCamera* cam = ren->GetActiveCamera();
  cam->SetPosition(0, 5, 9);
  cam->SetFocalPoint(0, 0, 0);
  cam->SetViewAngle(35);
  ren->ResetCameraClippingRange(-5, 5, -1, 5, -5, 5);
  vtkRayMapperStatistics* s = mapper->GetStatistics();

  win->Render();
  RM_CHECK(s->GetCounter("shadow_rays") == 0 && s->GetCounter("ao_rays") == 0);
  RM_CHECK(!s->GetEffect("soft_shadows") && !s->GetEffect("ambient_occlusion"));

  // The light straight above the cloud; the floor right under the cloud's centre is in
  // shadow, a floor point far to the side is not.
  mapper->AutomaticShadowLightOff();
  mapper->SetShadowLightPosition(0, 12, 0);
  mapper->SetShadowLightSize(3);
  mapper->SetShadowRays(4);
  win->Render();
  RM_CHECK(s->GetEffect("soft_shadows"));
  RM_CHECK(s->GetCounter("shadow_rays") == 16 * s->GetCounter("hits"));
  RM_CHECK(s->GetCounter("builds") == 1); // lighting changes rebuild nothing
  auto brightness = [&](double x, double z)
  {
    const double p[3] = { x, -0.5 + std::sqrt(39.5 * 39.5 - x * x - z * z) - 39.0, z };
    double d[3];
    rmtest::DisplayOf(ren, p, d);
    unsigned char* px = win->GetPixelData(int(d[0]), int(d[1]), int(d[0]), int(d[1]), 0);
    const int sum = px[0] + px[1] + px[2];
    delete[] px;
    return sum;
  };
  const int under = brightness(0.1, 0.1), aside = brightness(3.2, 1.5);
  std::printf("floor brightness under the cloud %d, to the side %d\n", under, aside);
  RM_CHECK(under < aside * 0.8);

  // Ambient occlusion on top.
  mapper->SetAmbientOcclusionSamples(8);
  win->Render();
  RM_CHECK(
    s->GetEffect("ambient_occlusion") && s->GetCounter("ao_rays") == 8 * s->GetCounter("hits"));

  return rmtest::CompareWithBaseline(win, argc, argv);
}
