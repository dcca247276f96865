// Bad input to vtkZSweepVolumeMapper gets a clear warning or error and loses nothing else:
// an empty grid draws nothing; a grid without scalars is an error; unsupported cells
// (pentagonal and hexagonal prisms of PentaHexa.vtk, a quadratic tetrahedron, polygons)
// and cells with NaN points or scalars are skipped with a warning while the picture of the
// valid cells is exactly what they alone give, with no NaN anywhere; a duplicated
// (overlapping) cell is warned about.
//
// usage: TestZSweepBadInput -D <dir with PentaHexa.vtk>
#include "RenderingTestHelpers.h"
#include "vtkRayMapperStatistics.h"
#include "vtkZSweepVolumeMapper.h"

#include "vtkCellType.h"
#include "vtkColorTransferFunction.h"
#include "vtkDoubleArray.h"
#include "vtkIdList.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointData.h"
#include "vtkTestUtilities.h"
#include "vtkUnstructuredGrid.h"
#include "vtkUnstructuredGridReader.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"

#include <cmath>
#include <limits>

namespace
{
// A cube [-1, 1]^3 of 5 tetrahedra with a point scalar.
vtkSmartPointer<vtkUnstructuredGrid> Cube()
{
  auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
  vtkNew<vtkPoints> points;
  vtkNew<vtkDoubleArray> s;
  s->SetName("s");
  for (int k = 0; k < 8; ++k)
  {
    const double x = (k & 1) ? 1 : -1, y = (k & 2) ? 1 : -1, z = (k & 4) ? 1 : -1;
    points->InsertNextPoint(x, y, z);
    s->InsertNextValue(0.5 + 0.2 * x + 0.1 * y - 0.15 * z);
  }
  grid->SetPoints(points);
  grid->GetPointData()->SetScalars(s);
  const vtkIdType tets[5][4] = { { 0, 1, 2, 4 }, { 1, 3, 2, 7 }, { 1, 4, 5, 7 }, { 2, 4, 7, 6 },
    { 1, 2, 4, 7 } };
  for (const auto& t : tets)
  {
    grid->InsertNextCell(VTK_TETRA, 4, t);
  }
  return grid;
}
}

int TestZSweepBadInput(int argc, char* argv[])
{
  vtkNew<vtkColorTransferFunction> color;
  color->AddRGBPoint(0, 0.2, 0.3, 0.9);
  color->AddRGBPoint(1, 1.0, 0.8, 0.2);
  vtkNew<vtkPiecewiseFunction> opacity;
  opacity->AddPoint(0, 0.1);
  opacity->AddPoint(1, 0.8);
  vtkNew<vtkVolumeProperty> property;
  property->SetColor(color);
  property->SetScalarOpacity(opacity);
  vtkNew<vtkZSweepVolumeMapper> mapper;
  vtkNew<vtkVolume> volume;
  volume->SetMapper(mapper);
  volume->SetProperty(property);
  vtkNew<vtkRenderer> ren;
  ren->AddVolume(volume);
  vtkNew<vtkRenderWindow> win;
  win->SetSize(100, 100);
  win->AddRenderer(ren);
  ren->GetActiveCamera()->SetPosition(2, 3, 6);
  ren->GetActiveCamera()->SetFocalPoint(0, 0, 0);
  rmtest::EventCounter events;
  events.Observe(mapper);
  bool ok = true;
  auto check = [&](bool condition, const char* what) {
    std::printf("%s %s\n", condition ? "ok  " : "FAIL", what);
    ok = ok && condition;
  };
  auto show = [&](vtkUnstructuredGrid* grid) {
    mapper->SetInputData(grid);
    ren->ResetCameraClippingRange(-2, 2, -2, 2, -2, 2);
    win->Render();
    return rmtest::ReadRGB(win);
  };
  auto lit = [](const std::vector<unsigned char>& rgb) {
    std::size_t n = 0;
    for (std::size_t k = 0; k < rgb.size(); k += 3)
    {
      n += rgb[k] + rgb[k + 1] + rgb[k + 2] > 0;
    }
    return n;
  };

  vtkNew<vtkUnstructuredGrid> empty;
  check(lit(show(empty)) == 0 && events.Errors == 0 && events.Warnings == 0,
    "an empty grid draws nothing, silently");

  const auto clean = Cube();
  const auto reference = show(clean);
  check(lit(reference) > 1000, "the cube is drawn");

  auto noScalars = Cube();
  noScalars->GetPointData()->SetScalars(nullptr);
  show(noScalars);
  show(noScalars);
  check(events.Errors == 1 && events.Last.find("no scalars") != std::string::npos,
    "no scalars: one clear error, not one per render");

  // Bad cells added to the clean cube: the picture must not change.
  auto bad = Cube();
  const vtkIdType far = bad->GetPoints()->InsertNextPoint(0, 0, std::nan(""));
  vtkDoubleArray::SafeDownCast(bad->GetPointData()->GetScalars())->InsertNextValue(0.5);
  const vtkIdType nanTet[4] = { 0, 1, 2, far };
  bad->InsertNextCell(VTK_TETRA, 4, nanTet);
  const vtkIdType far2 = bad->GetPoints()->InsertNextPoint(3, 3, 3);
  vtkDoubleArray::SafeDownCast(bad->GetPointData()->GetScalars())
    ->InsertNextValue(std::numeric_limits<double>::quiet_NaN());
  const vtkIdType nanScalar[4] = { 3, 5, 6, far2 };
  bad->InsertNextCell(VTK_TETRA, 4, nanScalar);
  const vtkIdType quadratic[10] = { 0, 1, 2, 4, 0, 1, 2, 4, 0, 1 };
  bad->InsertNextCell(VTK_QUADRATIC_TETRA, 10, quadratic);
  const vtkIdType triangle[3] = { 0, 1, 2 };
  bad->InsertNextCell(VTK_TRIANGLE, 3, triangle);
  const int warningsBefore = events.Warnings;
  const auto withBad = show(bad);
  check(withBad == reference, "bad cells leave exactly the picture of the good ones");
  check(events.Warnings - warningsBefore == 4, "one warning each: NaN point, NaN scalar, "
                                                "unsupported type, cells below 3D");
  check(mapper->GetStatistics()->GetCounter("cells") == 5, "the 5 good cells are rendered");

  // A duplicated cell overlaps its original: one warning naming the overlap, no NaN pixel
  // (the picture is drawn; what it shows there is undefined).
  auto overlapping = Cube();
  vtkNew<vtkIdList> firstCell;
  overlapping->GetCellPoints(0, firstCell);
  overlapping->InsertNextCell(overlapping->GetCellType(0), firstCell);
  const int beforeOverlap = events.Warnings;
  const auto overlapPicture = show(overlapping);
  check(events.Warnings == beforeOverlap + 1 && events.Last.find("overlap") != std::string::npos &&
      lit(overlapPicture) > 1000,
    "a duplicated cell: one warning naming the overlap, the cube still drawn");

  // Real cells VTK has but ZSweep does not split: pentagonal and hexagonal prisms.
  char* name = vtkTestUtilities::ExpandDataFileName(argc, argv, "PentaHexa.vtk");
  vtkNew<vtkUnstructuredGridReader> reader;
  reader->SetFileName(name);
  reader->Update();
  delete[] name;
  auto* prisms = reader->GetOutput();
  if (!prisms->GetPointData()->GetScalars())
  {
    vtkNew<vtkDoubleArray> s;
    s->SetName("s");
    s->SetNumberOfTuples(prisms->GetNumberOfPoints());
    s->Fill(0.5);
    prisms->GetPointData()->SetScalars(s);
  }
  const int before = events.Warnings;
  show(prisms);
  check(events.Warnings == before + 1 && events.Last.find("unsupported") != std::string::npos,
    "PentaHexa.vtk's prisms: one warning naming them unsupported");
  return ok ? EXIT_SUCCESS : EXIT_FAILURE;
}
