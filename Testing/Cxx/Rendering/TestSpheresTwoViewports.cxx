// Two renderers side by side, each with its own camera (perspective on the left, parallel
// on the right): each draws its spheres inside its own viewport only.
#include "RenderingTestHelpers.h"
#include "vtkCGTSphereMapper.h"

#include "vtkActor.h"
#include "vtkProperty.h"

int TestSpheresTwoViewports(int argc, char* argv[])
{
  auto lattice = rmtest::MakeLattice(4);
  vtkNew<vtkRenderWindow> win;
  win->SetSize(400, 200);
  vtkNew<vtkRenderer> left, right;
  left->SetViewport(0, 0, 0.5, 1);
  right->SetViewport(0.5, 0, 1, 1);
  left->SetBackground(0.2, 0.2, 0.2);
  right->SetBackground(0.3, 0.3, 0.4);
  vtkNew<vtkCGTSphereMapper> m1, m2;
  for (vtkCGTSphereMapper* m : { m1.Get(), m2.Get() })
  {
    m->SetInputData(lattice);
    m->SetRadiusArrayName("radius");
    m->SetScalarRange(0, 63);
  }
  m2->ScalarVisibilityOff();
  vtkNew<vtkActor> a1, a2;
  a1->SetMapper(m1);
  a2->SetMapper(m2);
  a2->GetProperty()->SetColor(0.9, 0.7, 0.2);
  left->AddActor(a1);
  right->AddActor(a2);
  win->AddRenderer(left);
  win->AddRenderer(right);
  left->GetActiveCamera()->SetPosition(3, 2, 5);
  left->GetActiveCamera()->SetFocalPoint(0, 0, 0);
  right->GetActiveCamera()->ParallelProjectionOn();
  right->GetActiveCamera()->SetPosition(0, 0, 8);
  right->GetActiveCamera()->SetFocalPoint(0, 0, 0);
  right->GetActiveCamera()->SetParallelScale(1.4);
  left->ResetCameraClippingRange();
  right->ResetCameraClippingRange();
  win->Render();

  // The front point of the lattice sphere at (1/3, 1/3, 1), i = j = 2, k = 3, lands in the
  // right half of the window at its closed-form depth.
  const double c[3] = { 1.0 / 3.0, 1.0 / 3.0, 1.0 };
  const double r = (2.0 / 3.0) * (0.2 + 0.25 * ((2 + 4 + 9) % 4) / 3.0);
  const double front[3] = { c[0], c[1], c[2] + r };
  double d[3];
  rmtest::DisplayOf(right, front, d);
  RM_CHECK(d[0] >= 200 && d[0] < 400);
  int x, y;
  const double buffer = rmtest::BufferDepthAt(right, front, x, y);
  const double exact = rmtest::SphereDepthAtPixel(right, x, y, c, r);
  std::printf(
    "right viewport depth at (%d, %d): buffer %.7f closed form %.7f\n", x, y, buffer, exact);
  RM_CHECK(std::fabs(buffer - exact) < 1e-5);
  // Nothing of the right renderer leaks into the left viewport: the left renderer's
  // corner pixel keeps its background.
  unsigned char* px = win->GetPixelData(2, 2, 2, 2, 0);
  const bool background = px[0] == 51 && px[1] == 51 && px[2] == 51;
  delete[] px;
  RM_CHECK(background);

  return rmtest::CompareWithBaseline(win, argc, argv);
}
