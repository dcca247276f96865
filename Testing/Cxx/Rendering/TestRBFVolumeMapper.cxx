// vtkRBFVolumeMapper in a VTK scene: a two-field particle cloud around an opaque sphere
// (vtkSphereSource through an ordinary OpenGL mapper). Checks that the opaque geometry
// stops the rays (fewer samples with it than without, its pixels keep its colour), that
// Kappa, Sigma, the sample distance and the transfer functions change the picture without a
// rebuild while the leaf size rebuilds, that shading and multi-field classification run
// only when asked for, and compares the picture with the baseline.
#include "RenderingTestHelpers.h"
#include "vtkRBFVolumeMapper.h"
#include "vtkRayMapperStatistics.h"

#include "vtkActor.h"
#include "vtkColorTransferFunction.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPolyDataMapper.h"
#include "vtkProperty.h"
#include "vtkSphereSource.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"

#include <random>

int TestRBFVolumeMapper(int argc, char* argv[])
{
  // 1500 particles in a shell around the origin, field 0 or 1 by the sign of x.
  std::vector<std::array<double, 3>> c;
  std::vector<double> r;
  std::mt19937 rng(3);
  std::normal_distribution<double> g(0.0, 1.0);
  for (int i = 0; i < 1500; ++i)
  {
    std::array<double, 3> p{ g(rng), g(rng), g(rng) };
    const double len = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    const double rad = 1.2 + 0.6 * std::fabs(g(rng));
    c.push_back({ p[0] / len * rad, p[1] / len * rad, p[2] / len * rad });
    r.push_back(0.12);
  }
  auto data = rmtest::MakeSpheres(c, r);
  vtkNew<vtkFloatArray> kind;
  kind->SetName("kind");
  for (const auto& p : c)
  {
    kind->InsertNextValue(p[0] < 0 ? 7.f : 11.f);
  }
  data->GetPointData()->AddArray(kind);

  vtkNew<vtkRBFVolumeMapper> mapper;
  mapper->SetInputData(data);
  mapper->SetRadiusArrayName("radius");
  mapper->SetSampleDistance(0.03);
  vtkNew<vtkVolumeProperty> property;
  property->SetIndependentComponents(1);
  for (int m = 0; m < 2; ++m)
  {
    vtkNew<vtkColorTransferFunction> color;
    color->AddRGBPoint(0.0, m ? 0.1 : 0.9, 0.4, m ? 0.9 : 0.1);
    color->AddRGBPoint(2.0, 1.0, 1.0, 0.8);
    vtkNew<vtkPiecewiseFunction> opacity;
    opacity->AddPoint(0.0, 0.0);
    opacity->AddPoint(0.2, 0.0);
    opacity->AddPoint(1.5, 0.6);
    property->SetColor(m, color);
    property->SetScalarOpacity(m, opacity);
    property->SetScalarOpacityUnitDistance(m, 1.0);
  }
  vtkNew<vtkVolume> volume;
  volume->SetMapper(mapper);
  volume->SetProperty(property);

  vtkNew<vtkSphereSource> ball;
  ball->SetRadius(0.9);
  ball->SetThetaResolution(48);
  ball->SetPhiResolution(48);
  vtkNew<vtkPolyDataMapper> ballMapper;
  ballMapper->SetInputConnection(ball->GetOutputPort());
  vtkNew<vtkActor> ballActor;
  ballActor->SetMapper(ballMapper);
  ballActor->GetProperty()->SetColor(0.3, 0.8, 0.3);

  vtkNew<vtkRenderer> ren;
  ren->AddVolume(volume);
  ren->SetBackground(0.1, 0.1, 0.15);
  vtkNew<vtkRenderWindow> win;
  win->SetSize(300, 300);
  win->SetMultiSamples(0);
  win->AddRenderer(ren);
  vtkCamera* cam = ren->GetActiveCamera();
  cam->SetPosition(0, 1.5, 7);
  cam->SetFocalPoint(0, 0, 0);
  cam->SetViewAngle(35);
  ren->ResetCameraClippingRange(-3, 3, -3, 3, -3, 3);
  vtkRayMapperStatistics* s = mapper->GetStatistics();

  win->Render();
  const long long samplesAlone = s->GetCounter("samples");
  RM_CHECK(s->GetCounter("builds") == 1 && s->GetCounter("particles") == 1500);
  RM_CHECK(s->GetCounter("fields") == 1 && !s->GetEffect("multi_field"));
  RM_CHECK(!s->GetEffect("shading"));
  // Nothing opaque in the scene: the depth buffer is not read.
  RM_CHECK(!s->GetEffect("opaque_depth"));

  // An opaque ball between the camera and the cloud stops the rays that meet it: they take
  // no sample at all.
  ball->SetCenter(0, 0.3, 4.6);
  ball->SetRadius(0.7);
  ren->AddActor(ballActor);
  win->Render();
  std::printf("samples without the ball %lld, behind a ball in front %lld\n", samplesAlone,
    s->GetCounter("samples"));
  RM_CHECK(s->GetCounter("samples") < 0.8 * samplesAlone);
  RM_CHECK(s->GetEffect("opaque_depth"));
  // The ball inside the shell: the volume in front of it is thin.
  ball->SetCenter(0, 0, 0);
  ball->SetRadius(0.9);
  win->Render();
  // The ball's centre pixel shows green (the volume is thin in front of it).
  {
    const double centre[3] = { 0, 0, 0.9 };
    double d[3];
    rmtest::DisplayOf(ren, centre, d);
    unsigned char* px = win->GetPixelData(int(d[0]), int(d[1]), int(d[0]), int(d[1]), 0);
    std::printf("ball centre pixel %d %d %d\n", px[0], px[1], px[2]);
    const bool green = px[1] > px[0] && px[1] > px[2];
    delete[] px;
    RM_CHECK(green);
  }

  // Render parameters and transfer functions rebuild nothing.
  mapper->SetSigma(2.5);
  mapper->SetKappa(1.3);
  mapper->SetSampleDistance(0.025);
  property->GetScalarOpacity(0)->AddPoint(1.0, 0.5);
  win->Render();
  RM_CHECK(s->GetCounter("builds") == 1 && s->GetCounter("builds_this_render") == 0);

  // Two fields and shading.
  mapper->SetFieldArrayName("kind");
  property->ShadeOn();
  property->SetAmbient(0.3);
  property->SetDiffuse(0.7);
  win->Render();
  RM_CHECK(s->GetCounter("fields") == 2 && s->GetEffect("multi_field"));
  RM_CHECK(s->GetEffect("shading"));
  RM_CHECK(s->GetCounter("builds") == 2); // the fields rebuilt the particles and the BVH

  // The leaf size rebuilds the BVH only.
  mapper->SetLeafSize(4);
  win->Render();
  RM_CHECK(s->GetCounter("builds") == 3);

  return rmtest::CompareWithBaseline(win, argc, argv);
}
