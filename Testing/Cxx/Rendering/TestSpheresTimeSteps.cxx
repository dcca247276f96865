// Time-varying data: the LAMMPS dump reader feeds the mapper two time steps of a real
// LAMMPS run. A new time step rebuilds the spheres and the grid (and nothing is rebuilt
// when the camera moves); going back to the first step gives its picture again.
#include "RenderingTestHelpers.h"
#include "vtkCGTSphereMapper.h"
#include "vtkLAMMPSDumpReader.h"
#include "vtkRayMapperStatistics.h"

#include "vtkActor.h"
#include "vtkInformation.h"
#include "vtkStreamingDemandDrivenPipeline.h"

int TestSpheresTimeSteps(int argc, char* argv[])
{
  const char* dump = argc > 1 ? argv[1] : nullptr;
  RM_CHECK(dump != nullptr);
  vtkNew<vtkLAMMPSDumpReader> reader;
  reader->SetFileName(dump);
  vtkNew<vtkCGTSphereMapper> mapper;
  mapper->SetRadius(0.45);
  mapper->SetScalarModeToUsePointFieldData();
  mapper->SelectColorArray("type");
  mapper->SetScalarRange(1, 2);
  vtkNew<vtkActor> actor;
  actor->SetMapper(mapper);
  vtkNew<vtkRenderer> ren;
  ren->AddActor(actor);
  vtkNew<vtkRenderWindow> win;
  win->SetSize(160, 160);
  win->AddRenderer(ren);

  // Each time step arrives as a new data object, as ParaView's representations deliver it.
  auto showStep = [&](double t)
  {
    reader->UpdateTimeStep(t);
    vtkNew<vtkPolyData> step;
    step->ShallowCopy(reader->GetOutput());
    mapper->SetInputData(step);
    win->Render();
    return rmtest::ReadRGB(win);
  };
  reader->UpdateInformation();
  vtkInformation* info = reader->GetOutputInformation(0);
  RM_CHECK(info->Length(vtkStreamingDemandDrivenPipeline::TIME_STEPS()) == 2);
  ren->ResetCamera(0, 7, 0, 7, 0, 7);
  vtkRayMapperStatistics* s = mapper->GetStatistics();

  const auto first = showStep(0.0);
  RM_CHECK(s->GetCounter("builds") == 1 && s->GetCounter("spheres") == 256);
  ren->GetActiveCamera()->Azimuth(10);
  win->Render();
  RM_CHECK(s->GetCounter("builds") == 1); // same step, new view: nothing rebuilt
  ren->GetActiveCamera()->Azimuth(-10);
  const auto second = showStep(100.0);
  RM_CHECK(s->GetCounter("builds") == 2); // the next step: spheres and grid rebuilt
  RM_CHECK(s->GetPhaseTime("grid_build") > 0);
  RM_CHECK(second != first); // the atoms moved
  const auto again = showStep(0.0);
  RM_CHECK(again == first);
  RM_CHECK(s->GetCounter("builds") == 3);
  std::printf(
    "time steps: %lld builds, pictures differ between steps and repeat\n", s->GetCounter("builds"));
  return EXIT_SUCCESS;
}
