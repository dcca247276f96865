// A lattice of spheres coloured through a lookup table, seen with a parallel projection.
#include "RenderingTestHelpers.h"
#include "vtkCGTSphereMapper.h"
#include "vtkRayMapperStatistics.h"

#include "vtkActor.h"
#include "vtkLookupTable.h"
#include "vtkProperty.h"

int TestSpheresParallelProjection(int argc, char* argv[])
{
  auto lattice = rmtest::MakeLattice(5);
  vtkNew<vtkLookupTable> lut;
  lut->SetHueRange(0.667, 0.0);
  lut->Build();
  vtkNew<vtkCGTSphereMapper> mapper;
  mapper->SetInputData(lattice);
  mapper->SetRadiusArrayName("radius");
  mapper->SetLookupTable(lut);
  mapper->SetScalarRange(0, 124);
  vtkNew<vtkActor> actor;
  actor->SetMapper(mapper);
  actor->GetProperty()->SetAmbient(0.1);
  actor->GetProperty()->SetSpecular(0.3);
  actor->GetProperty()->SetSpecularPower(20);

  vtkNew<vtkRenderer> ren;
  ren->AddActor(actor);
  ren->SetBackground(1, 1, 1);
  vtkNew<vtkRenderWindow> win;
  win->SetSize(300, 300);
  win->AddRenderer(ren);
  vtkCamera* cam = ren->GetActiveCamera();
  cam->ParallelProjectionOn();
  cam->SetPosition(0, 0, 10);
  cam->SetFocalPoint(0, 0, 0);
  cam->SetViewUp(0, 1, 0);
  cam->SetParallelScale(1.5);
  ren->ResetCameraClippingRange();
  win->Render();

  // The sphere at (1, 1, 1) (radius from the lattice rule) has its front point on the axis
  // of the parallel rays: its depth is in the buffer.
  const double r = 0.5 * (0.2 + 0.25 * ((4 + 8 + 12) % 4) / 3.0);
  const double front[3] = { 1, 1, 1 + r };
  const double center[3] = { 1, 1, 1 };
  int x, y;
  const double buffer = rmtest::BufferDepthAt(ren, front, x, y);
  const double exact = rmtest::SphereDepthAtPixel(ren, x, y, center, r);
  std::printf("depth at pixel (%d, %d): buffer %.7f closed form %.7f\n", x, y, buffer, exact);
  RM_CHECK(std::fabs(buffer - exact) < 1e-5);
  RM_CHECK(mapper->GetStatistics()->GetCounter("spheres") == 125);

  return rmtest::CompareWithBaseline(win, argc, argv);
}
