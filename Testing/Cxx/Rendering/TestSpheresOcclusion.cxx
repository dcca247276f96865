// Ray-traced spheres and ordinary OpenGL polygons hide each other through the depth buffer:
// a plane cuts two spheres (their caps poke through it), a quad in front hides part of a
// third. Probes check the depth buffer against closed-form depths and the colours; the
// image is compared with the baseline.
#include "RenderingTestHelpers.h"
#include "vtkCGTSphereMapper.h"

#include "vtkActor.h"
#include "vtkPlaneSource.h"
#include "vtkPolyDataMapper.h"
#include "vtkProperty.h"
#include "vtkRenderWindowInteractor.h"

int TestSpheresOcclusion(int argc, char* argv[])
{
  auto spheres =
    rmtest::MakeSpheres({ { -1.2, 0, 0 }, { 0, 0, 0 }, { 1.2, 0, 0 } }, { 0.5, 0.5, 0.5 });
  vtkNew<vtkCGTSphereMapper> mapper;
  mapper->SetInputData(spheres);
  mapper->SetRadiusArrayName("radius");
  mapper->SetScalarRange(0, 2);
  vtkNew<vtkActor> sphereActor;
  sphereActor->SetMapper(mapper);
  sphereActor->GetProperty()->SetSpecular(0.4);
  sphereActor->GetProperty()->SetSpecularPower(30);

  // A red plane at z = 0.2 under the middle and right spheres.
  vtkNew<vtkPlaneSource> plane;
  plane->SetOrigin(-0.6, -1, 0.2);
  plane->SetPoint1(2, -1, 0.2);
  plane->SetPoint2(-0.6, 1, 0.2);
  vtkNew<vtkPolyDataMapper> planeMapper;
  planeMapper->SetInputConnection(plane->GetOutputPort());
  vtkNew<vtkActor> planeActor;
  planeActor->SetMapper(planeMapper);
  planeActor->GetProperty()->SetColor(1, 0, 0);
  planeActor->GetProperty()->LightingOff();

  // A green quad at z = 1 in front of the lower half of the left sphere.
  vtkNew<vtkPlaneSource> quad;
  quad->SetOrigin(-1.8, -0.8, 1);
  quad->SetPoint1(-0.6, -0.8, 1);
  quad->SetPoint2(-1.8, -0.1, 1);
  vtkNew<vtkPolyDataMapper> quadMapper;
  quadMapper->SetInputConnection(quad->GetOutputPort());
  vtkNew<vtkActor> quadActor;
  quadActor->SetMapper(quadMapper);
  quadActor->GetProperty()->SetColor(0, 1, 0);
  quadActor->GetProperty()->LightingOff();

  vtkNew<vtkRenderer> ren;
  ren->AddActor(sphereActor);
  ren->AddActor(planeActor);
  ren->AddActor(quadActor);
  ren->SetBackground(0.1, 0.1, 0.2);
  vtkNew<vtkRenderWindow> win;
  win->SetSize(400, 300);
  win->AddRenderer(ren);
  vtkCamera* cam = ren->GetActiveCamera();
  cam->SetPosition(0, 0, 6);
  cam->SetFocalPoint(0, 0, 0);
  cam->SetViewUp(0, 1, 0);
  ren->ResetCameraClippingRange();
  win->Render();

  auto rgbAt = [&](const double p[3])
  {
    double d[3];
    rmtest::DisplayOf(ren, p, d);
    const int x = static_cast<int>(std::floor(d[0])), y = static_cast<int>(std::floor(d[1]));
    unsigned char* px = win->GetPixelData(x, y, x, y, 0);
    std::array<int, 3> c{ px[0], px[1], px[2] };
    delete[] px;
    return c;
  };
  // Depth in the buffer at the pixel showing p, and the closed-form depth of the sphere
  // (c, 0.5) along that pixel's ray.
  auto sphereDepths = [&](const double p[3], const double c[3], double& buffer, double& exact)
  {
    int x, y;
    buffer = rmtest::BufferDepthAt(ren, p, x, y);
    exact = rmtest::SphereDepthAtPixel(ren, x, y, c, 0.5);
    std::printf(
      "sphere depth at pixel (%d, %d): buffer %.7f closed form %.7f\n", x, y, buffer, exact);
  };
  double buffer, exact;

  // The middle sphere's front point (0, 0, 0.5) is in front of the plane: its depth is in
  // the buffer, and the pixel is not the plane's red.
  const double middle[3] = { 0, 0, 0 };
  const double front[3] = { 0, 0, 0.5 };
  sphereDepths(front, middle, buffer, exact);
  RM_CHECK(std::fabs(buffer - exact) < 1e-5);
  RM_CHECK(rgbAt(front) != (std::array<int, 3>{ 255, 0, 0 }));
  // At (0, 0.48) the sphere surface is at z = 0.14 < 0.2: the plane hides it.
  const double underPlane[3] = { 0, 0.48, 0.2 };
  int x, y;
  RM_CHECK(std::fabs(rmtest::BufferDepthAt(ren, underPlane, x, y) -
                     rmtest::WindowDepthOf(ren, underPlane)) < 1e-3);
  RM_CHECK(rgbAt(underPlane) == (std::array<int, 3>{ 255, 0, 0 }));
  // The green quad hides the lower part of the left sphere.
  const double onQuad[3] = { -1.2, -0.3, 1 };
  RM_CHECK(rgbAt(onQuad) == (std::array<int, 3>{ 0, 255, 0 }));
  // Above the quad the left sphere is visible at its closed-form depth.
  const double left[3] = { -1.2, 0, 0 };
  const double leftFront[3] = { -1.2, 0.3, 0.4 };
  sphereDepths(leftFront, left, buffer, exact);
  RM_CHECK(std::fabs(buffer - exact) < 1e-5);

  return rmtest::CompareWithBaseline(win, argc, argv);
}
