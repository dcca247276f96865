// A screenshot larger than the window is rendered in tiles (vtkWindowToImageFilter with a
// scale, the mechanism of ParaView's SaveScreenshot): the picture must be the same at any
// tiling. 480 x 360 is made in one piece, from 2 x 2 tiles of 240 x 180 and from 3 x 3
// tiles of 160 x 120; all three must agree pixel for pixel.
#include "RenderingTestHelpers.h"
#include "vtkCGTSphereMapper.h"

#include "vtkActor.h"
#include "vtkImageData.h"
#include "vtkPNGWriter.h"
#include "vtkProperty.h"
#include "vtkTestUtilities.h"
#include "vtkWindowToImageFilter.h"

#include <cstdlib>

namespace
{
vtkSmartPointer<vtkImageData> Screenshot(vtkPolyData* data, int width, int height, int scale)
{
  vtkNew<vtkCGTSphereMapper> mapper;
  mapper->SetInputData(data);
  mapper->SetRadiusArrayName("radius");
  mapper->SetScalarRange(0, 215);
  vtkNew<vtkActor> actor;
  actor->SetMapper(mapper);
  actor->GetProperty()->SetSpecular(0.3);
  actor->GetProperty()->SetSpecularPower(25);
  vtkNew<vtkRenderer> ren;
  ren->AddActor(actor);
  ren->SetBackground(0.1, 0.15, 0.2);
  vtkCamera* cam = ren->GetActiveCamera();
  cam->SetPosition(2.5, 1.5, 4);
  cam->SetFocalPoint(0, 0, 0);
  cam->SetViewAngle(35);
  cam->SetClippingRange(2, 8);
  vtkNew<vtkRenderWindow> win;
  win->SetSize(width, height);
  win->AddRenderer(ren);
  win->Render();
  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(win);
  grab->SetScale(scale);
  grab->ReadFrontBufferOff();
  grab->Update();
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->DeepCopy(grab->GetOutput());
  return image;
}

long Differing(vtkImageData* a, vtkImageData* b)
{
  int da[3], db[3];
  a->GetDimensions(da);
  b->GetDimensions(db);
  if (da[0] != db[0] || da[1] != db[1])
  {
    return -1;
  }
  auto* pa = static_cast<unsigned char*>(a->GetScalarPointer());
  auto* pb = static_cast<unsigned char*>(b->GetScalarPointer());
  const int na = a->GetNumberOfScalarComponents();
  const int nb = b->GetNumberOfScalarComponents();
  long differing = 0;
  for (long p = 0; p < static_cast<long>(da[0]) * da[1]; ++p)
  {
    for (int c = 0; c < 3; ++c)
    {
      if (pa[na * p + c] != pb[nb * p + c])
      {
        ++differing;
        break;
      }
    }
  }
  return differing;
}
}

int TestSpheresTiledRender(int argc, char* argv[])
{
  auto lattice = rmtest::MakeLattice(6);
  auto whole = Screenshot(lattice, 480, 360, 1);
  auto tiles2 = Screenshot(lattice, 240, 180, 2);
  auto tiles3 = Screenshot(lattice, 160, 120, 3);
  const long d2 = Differing(whole, tiles2);
  const long d3 = Differing(whole, tiles3);
  std::printf("pixels differing from the untiled 480x360: 2x2 tiles %ld, 3x3 tiles %ld\n", d2, d3);
  if (d2 != 0 || d3 != 0)
  {
    const char* tmp = vtkTestUtilities::GetArgOrEnvOrDefault("-T", argc, argv, "", ".");
    vtkNew<vtkPNGWriter> writer;
    writer->SetInputData(tiles3);
    writer->SetFileName((std::string(tmp) + "/TestSpheresTiledRender-3x3.png").c_str());
    writer->Write();
    delete[] tmp;
  }
  RM_CHECK(d2 == 0);
  RM_CHECK(d3 == 0);

  // The 3 x 3 tiled image is also the regression image.
  return rmtest::CompareWithBaseline(raymappers::test::fromImageData(tiles3), argc, argv);
}
