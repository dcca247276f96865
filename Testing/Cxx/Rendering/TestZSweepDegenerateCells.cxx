// Degenerate and inverted cells through vtkZSweepVolumeMapper, on a 3^3 lattice of warped
// hexahedra with a point scalar, its points stored as floats (VTK's default) and as doubles:
// - zero-volume cells added to it (four coplanar points, rounded; a tetrahedron with a
//   repeated point id; a hexahedron collapsed to a quadrilateral by its ids and one onto
//   coincident points; a sliver at half the volume threshold): exactly one warning, naming
//   zero volume and their count, and the picture exactly the lattice's alone (whose
//   equality with the clean picture also rules out NaN pixels); a re-render warns no more;
// - every other hexahedron inverted (its top face listed first): the same picture, no
//   warning, the inverted cells counted (counter inverted_cells).
//
// usage: TestZSweepDegenerateCells
#include "RenderingTestHelpers.h"
#include "vtkRayMapperStatistics.h"
#include "vtkZSweepVolumeMapper.h"

#include "vtkCellType.h"
#include "vtkColorTransferFunction.h"
#include "vtkDoubleArray.h"
#include "vtkIdList.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointData.h"
#include "vtkUnstructuredGrid.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"

#include <array>
#include <cmath>
#include <string>

namespace
{
constexpr int N = 3; // cells along each axis

vtkIdType PointId(int i, int j, int k)
{
  return (k * (N + 1) + j) * (N + 1) + i;
}

// The lattice over [-1, 1]^3, its interior points moved by up to 0.2 of a cell, the scalar
// s = 0.5 + 0.3 sin(2x) cos(y) + 0.1 z; points of the given type (VTK_FLOAT, VTK_DOUBLE).
vtkSmartPointer<vtkUnstructuredGrid> Lattice(int pointType)
{
  auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
  vtkNew<vtkPoints> points;
  points->SetDataType(pointType);
  vtkNew<vtkDoubleArray> s;
  s->SetName("s");
  const double h = 2.0 / N;
  for (int k = 0; k <= N; ++k)
  {
    for (int j = 0; j <= N; ++j)
    {
      for (int i = 0; i <= N; ++i)
      {
        const bool interior = i > 0 && j > 0 && k > 0 && i < N && j < N && k < N;
        const double wobble = interior ? 0.2 * h : 0.0;
        const double x = -1 + i * h + wobble * std::sin(1.7 * (i + 2 * j + 3 * k));
        const double y = -1 + j * h + wobble * std::cos(2.3 * (3 * i + j + k));
        const double z = -1 + k * h + wobble * std::sin(0.9 * (i + j + 5 * k));
        points->InsertNextPoint(x, y, z);
        s->InsertNextValue(0.5 + 0.3 * std::sin(2 * x) * std::cos(y) + 0.1 * z);
      }
    }
  }
  grid->SetPoints(points);
  grid->GetPointData()->SetScalars(s);
  for (int k = 0; k < N; ++k)
  {
    for (int j = 0; j < N; ++j)
    {
      for (int i = 0; i < N; ++i)
      {
        const vtkIdType hex[8] = { PointId(i, j, k), PointId(i + 1, j, k), PointId(i + 1, j + 1, k),
          PointId(i, j + 1, k), PointId(i, j, k + 1), PointId(i + 1, j, k + 1),
          PointId(i + 1, j + 1, k + 1), PointId(i, j + 1, k + 1) };
        grid->InsertNextCell(VTK_HEXAHEDRON, 8, hex);
      }
    }
  }
  return grid;
}

vtkIdType AddPoint(vtkUnstructuredGrid* grid, double x, double y, double z)
{
  vtkDoubleArray::SafeDownCast(grid->GetPointData()->GetScalars())->InsertNextValue(0.5);
  return grid->GetPoints()->InsertNextPoint(x, y, z);
}

// Five cells of zero volume, inside the lattice or on its faces.
int AddZeroVolumeCells(vtkUnstructuredGrid* grid)
{
  // Four points of a tilted plane (their volume rounding noise, not exactly 0: in float
  // points 5e-11, 54 times the 1e-12 D^3 threshold; in double points 1.4e-18).
  const double u[3] = { 0.6, 0.7, 0.2 }, v[3] = { -0.7, 0.62, -0.1 };
  const double ab[4][2] = { { -0.3, -0.2 }, { 0.4, -0.1 }, { 0.1, 0.5 }, { -0.2, 0.3 } };
  vtkIdType flat[4];
  for (int q = 0; q < 4; ++q)
  {
    flat[q] = AddPoint(grid, 0.05 + ab[q][0] * u[0] + ab[q][1] * v[0],
      0.1 + ab[q][0] * u[1] + ab[q][1] * v[1], 0.1 + ab[q][0] * u[2] + ab[q][1] * v[2]);
  }
  grid->InsertNextCell(VTK_TETRA, 4, flat);
  // A repeated id on a face of the first hexahedron.
  const vtkIdType repeated[4] = { PointId(0, 0, 0), PointId(1, 0, 0), PointId(1, 1, 0),
    PointId(1, 0, 0) };
  grid->InsertNextCell(VTK_TETRA, 4, repeated);
  // A hexahedron collapsed onto an interior quadrilateral of the lattice.
  const vtkIdType quad[4] = { PointId(1, 1, 1), PointId(2, 1, 1), PointId(2, 2, 1),
    PointId(1, 2, 1) };
  const vtkIdType collapsed[8] = { quad[0], quad[1], quad[2], quad[3], quad[0], quad[1], quad[2],
    quad[3] };
  grid->InsertNextCell(VTK_HEXAHEDRON, 8, collapsed);
  // A hexahedron whose top points coincide with its bottom ones.
  vtkIdType coincident[8];
  const double corners[4][2] = { { -0.5, -0.4 }, { 0.3, -0.5 }, { 0.4, 0.3 }, { -0.4, 0.2 } };
  for (int layer = 0; layer < 2; ++layer)
  {
    for (int q = 0; q < 4; ++q)
    {
      coincident[4 * layer + q] = AddPoint(grid, corners[q][0], corners[q][1], -0.25);
    }
  }
  grid->InsertNextCell(VTK_HEXAHEDRON, 8, coincident);
  // A sliver of half the threshold's volume: a = (-1, -1, -e/2), b = (1, -1, e/2),
  // c = (1, 1, -e/2), d = (-1, 1, e/2) scaled by 0.3 enclose V = 4 e / 3 (times 0.027), and
  // the threshold is 1e-12 of the box's diagonal cubed: (0.3 sqrt(8))^3.
  const double e = 0.5 * 1e-12 * std::pow(std::sqrt(8.0), 3) * 0.75;
  const vtkIdType sliver[4] = { AddPoint(grid, -0.3, -0.3, 0.3 * -0.5 * e),
    AddPoint(grid, 0.3, -0.3, 0.3 * 0.5 * e), AddPoint(grid, 0.3, 0.3, 0.3 * -0.5 * e),
    AddPoint(grid, -0.3, 0.3, 0.3 * 0.5 * e) };
  grid->InsertNextCell(VTK_TETRA, 4, sliver);
  return 5;
}
}

int TestZSweepDegenerateCells(int, char*[])
{
  vtkNew<vtkColorTransferFunction> color;
  color->AddRGBPoint(0.1, 0.2, 0.3, 0.9);
  color->AddRGBPoint(0.5, 0.2, 0.9, 0.3);
  color->AddRGBPoint(0.9, 1.0, 0.8, 0.2);
  vtkNew<vtkPiecewiseFunction> opacity;
  opacity->AddPoint(0.1, 0.05);
  opacity->AddPoint(0.9, 0.6);
  vtkNew<vtkVolumeProperty> property;
  property->SetColor(color);
  property->SetScalarOpacity(opacity);
  property->SetScalarOpacityUnitDistance(0.5);
  vtkNew<vtkZSweepVolumeMapper> mapper;
  vtkNew<vtkVolume> volume;
  volume->SetMapper(mapper);
  volume->SetProperty(property);
  vtkNew<vtkRenderer> ren;
  ren->AddVolume(volume);
  vtkNew<vtkRenderWindow> win;
  win->SetSize(120, 120);
  win->AddRenderer(ren);
  ren->GetActiveCamera()->SetPosition(2.5, 3.2, 5.5);
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
  vtkRayMapperStatistics* stats = mapper->GetStatistics();

  for (const int type : { VTK_FLOAT, VTK_DOUBLE })
  {
    const char* name = type == VTK_FLOAT ? "float points" : "double points";
    std::printf("%s:\n", name);
    const auto clean = Lattice(type);
    const int beforeClean = events.Warnings;
    const auto reference = show(clean);
    check(lit(reference) > 3000 && events.Warnings == beforeClean,
      "the lattice is drawn, silently");
    const auto cells = stats->GetCounter("cells");

    auto degenerate = Lattice(type);
    const int added = AddZeroVolumeCells(degenerate);
    const int before = events.Warnings;
    const auto withDegenerate = show(degenerate);
    const std::string expected = std::to_string(added) + " cells of zero volume";
    check(events.Warnings == before + 1 && events.Last.find(expected) != std::string::npos,
      "zero-volume cells: exactly one warning, naming zero volume and their count");
    check(withDegenerate == reference && stats->GetCounter("cells") == cells,
      "zero-volume cells: exactly the lattice's picture, from the lattice's cells");
    show(degenerate);
    check(events.Warnings == before + 1, "a re-render of the same grid warns no more");
  }

  const auto clean = Lattice(VTK_FLOAT);
  const auto reference = show(clean);
  const auto cells = stats->GetCounter("cells");
  check(stats->GetCounter("inverted_cells") == 0, "the lattice's hexahedra are positive");
  auto inverted = Lattice(VTK_FLOAT);
  vtkNew<vtkIdList> ids;
  vtkIdType flipped = 0;
  for (vtkIdType c = 1; c < inverted->GetNumberOfCells(); c += 2, ++flipped)
  {
    inverted->GetCellPoints(c, ids);
    vtkIdType hex[8];
    for (int k = 0; k < 8; ++k)
    {
      hex[k] = ids->GetId((k + 4) % 8); // the top face first: the mirror image
    }
    inverted->ReplaceCell(c, 8, hex);
  }
  const int beforeInverted = events.Warnings;
  const auto invertedPicture = show(inverted);
  check(invertedPicture == reference && events.Warnings == beforeInverted &&
      stats->GetCounter("inverted_cells") == flipped && stats->GetCounter("cells") == cells,
    "every other hexahedron inverted: the same picture, no warning, the inverted ones counted");
  check(events.Errors == 0, "no error");
  return ok ? EXIT_SUCCESS : EXIT_FAILURE;
}
