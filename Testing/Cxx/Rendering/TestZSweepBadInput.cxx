// vtkZSweepVolumeMapper on bad input. Each case gives exactly the warnings (or the error)
// it names, renders exactly the picture of the valid cells alone (tolerance 0) and leaves a
// float frame without NaN, infinite or out-of-range values (ValidateFrames):
//   - an empty grid (one warning, nothing drawn); a grid without scalars (one error, not
//     one per render);
//   - cells with a NaN point, a NaN or infinite point scalar, a NaN cell scalar, and cells
//     of types the sweep does not render (triangles, quads, a quadratic tetrahedron, a
//     polyhedron) mixed in: one warning per kind (the types named with their counts), the
//     picture of the good cells;
//   - integer point scalars (the picture of the double ones, silently); 3-component
//     scalars (one warning, the first component);
//   - a duplicated (overlapping) cell (one warning naming the overlap);
//   - PentaHexa.vtk's pentagonal and hexagonal prisms (one warning naming them);
//   - NaN and out-of-range property values (one warning each; NaN keeps the value, the
//     others are clamped: the picture of the bound set directly);
//   - degenerate cameras (zero view angle drawn; the eye at the focal point and a NaN
//     position: one warning each, nothing drawn).
//
// usage: TestZSweepBadInput -D <dir with PentaHexa.vtk>
#include "BadInputViewer.h"
#include "RenderingTestHelpers.h"
#include "vtkZSweepVolumeMapper.h"

#include "vtkCellData.h"
#include "vtkCellType.h"
#include "vtkColorTransferFunction.h"
#include "vtkDoubleArray.h"
#include "vtkIdList.h"
#include "vtkIntArray.h"
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
using raymappers::test::RGBImage;

// A cube [-1, 1]^3 of 5 tetrahedra with the point scalar s (and an integer copy is of 4 s,
// for a colour function over [0, 4]), and the cell scalar c.
vtkSmartPointer<vtkUnstructuredGrid> Cube()
{
  auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
  vtkNew<vtkPoints> points;
  vtkNew<vtkDoubleArray> s, c, s3;
  vtkNew<vtkIntArray> is;
  s->SetName("s");
  is->SetName("is");
  s3->SetName("s3");
  s3->SetNumberOfComponents(3);
  c->SetName("c");
  for (int k = 0; k < 8; ++k)
  {
    const double x = (k & 1) ? 1 : -1, y = (k & 2) ? 1 : -1, z = (k & 4) ? 1 : -1;
    points->InsertNextPoint(x, y, z);
    const double v = 0.5 + 0.2 * x + 0.1 * y - 0.15 * z;
    s->InsertNextValue(v);
    is->InsertNextValue(k % 5);
    s3->InsertNextTuple3(v, 1 - v, 0.25);
  }
  grid->SetPoints(points);
  grid->GetPointData()->SetScalars(s);
  grid->GetPointData()->AddArray(is);
  grid->GetPointData()->AddArray(s3);
  const vtkIdType tets[5][4] = { { 0, 1, 2, 4 }, { 1, 3, 2, 7 }, { 1, 4, 5, 7 }, { 2, 4, 7, 6 },
    { 1, 2, 4, 7 } };
  for (const auto& t : tets)
  {
    grid->InsertNextCell(VTK_TETRA, 4, t);
    c->InsertNextValue(0.2 + 0.1 * grid->GetNumberOfCells());
  }
  grid->GetCellData()->AddArray(c);
  return grid;
}

// The cube with bad cells added: a NaN point, NaN and infinite point scalars, and cells of
// types the sweep skips (2 triangles, 1 quad, 1 quadratic tetrahedron, 1 polyhedron).
vtkSmartPointer<vtkUnstructuredGrid> WithBadCells()
{
  auto bad = Cube();
  vtkPointData* pd = bad->GetPointData();
  auto addPoint = [&](double x, double y, double z, double s) {
    const vtkIdType id = bad->GetPoints()->InsertNextPoint(x, y, z);
    vtkDoubleArray::SafeDownCast(pd->GetScalars())->InsertNextValue(s);
    pd->GetArray("is")->InsertNextTuple1(0);
    pd->GetArray("s3")->InsertNextTuple3(s, 0, 0);
    return id;
  };
  auto addCell = [&](int type, std::vector<vtkIdType> ids) {
    bad->InsertNextCell(type, static_cast<vtkIdType>(ids.size()), ids.data());
    bad->GetCellData()->GetArray("c")->InsertNextTuple1(0.5);
  };
  addCell(VTK_TETRA, { 0, 1, 2, addPoint(0, 0, std::nan(""), 0.5) });
  addCell(VTK_TETRA, { 0, 1, 2, addPoint(0, std::numeric_limits<double>::infinity(), 0, 0.5) });
  addCell(VTK_TETRA, { 3, 5, 6, addPoint(3, 3, 3, std::nan("")) });
  addCell(VTK_TETRA, { 3, 5, 6, addPoint(3, 3, -3, std::numeric_limits<double>::infinity()) });
  addCell(VTK_QUADRATIC_TETRA, { 0, 1, 2, 4, 0, 1, 2, 4, 0, 1 });
  addCell(VTK_TRIANGLE, { 0, 1, 2 });
  addCell(VTK_TRIANGLE, { 4, 5, 6 });
  addCell(VTK_QUAD, { 0, 1, 3, 2 });
  // A polyhedron (the tetrahedron 0 1 2 4 given by its faces).
  const vtkIdType faces[] = { 3, 0, 2, 1, 3, 0, 1, 4, 3, 0, 4, 2, 3, 1, 2, 4 };
  const vtkIdType polyPoints[] = { 0, 1, 2, 4 };
  bad->InsertNextCell(VTK_POLYHEDRON, 4, polyPoints, 4, faces);
  bad->GetCellData()->GetArray("c")->InsertNextTuple1(0.5);
  return bad;
}

struct Viewer : rmtest::BadInputVolumeViewer<vtkZSweepVolumeMapper, vtkUnstructuredGrid>
{
  Viewer()
  {
    vtkNew<vtkColorTransferFunction> color;
    color->AddRGBPoint(0, 0.2, 0.3, 0.9);
    color->AddRGBPoint(1, 1.0, 0.8, 0.2);
    vtkNew<vtkPiecewiseFunction> opacity;
    opacity->AddPoint(0, 0.1);
    opacity->AddPoint(1, 0.8);
    Property->SetColor(color);
    Property->SetScalarOpacity(opacity);
    Open(100, 2, 3, 6);
  }
};

std::size_t Lit(const RGBImage& image)
{
  std::size_t n = 0;
  for (std::size_t k = 0; k + 2 < image.rgb.size(); k += 3)
  {
    n += image.rgb[k] + image.rgb[k + 1] + image.rgb[k + 2] > 0;
  }
  return n;
}

void Cells(Viewer& v, const RGBImage& reference, int argc, char* argv[])
{
  rmtest::BadInputLog& log = v.Log;
  vtkNew<vtkUnstructuredGrid> empty;
  log.Check(Lit(v.Show(empty)) == 0, "an empty grid draws nothing");
  log.Warned(1, "no cells", "an empty grid");

  auto noScalars = Cube();
  noScalars->GetPointData()->SetScalars(nullptr);
  v.Show(noScalars);
  v.Render();
  log.Errored(1, "The input has no scalars to render", "no scalars: one error, not one per render");

  auto bad = WithBadCells();
  log.SameImage(v.Show(bad), reference, "bad cells: the picture of the good ones");
  log.Warned(3, "cells", "NaN point, NaN or infinite scalars (2 cells), skipped types");
  bool typesNamed = false;
  for (const std::string& t : v.Events.Texts)
  {
    typesNamed = typesNamed ||
      (t.find("1 vtkQuad,") != std::string::npos &&
        t.find("2 vtkTriangle") != std::string::npos &&
        t.find("1 vtkQuadraticTetra") != std::string::npos &&
        t.find("1 vtkPolyhedron") != std::string::npos);
  }
  log.Check(typesNamed, "one warning names the skipped types with their counts");
  log.Check(v.Mapper->GetStatistics()->GetCounter("cells") == 5, "the 5 good cells are rendered");
  log.ValidFrame("bad cells");
  v.Render();
  log.Silent("bad cells, rendered again");
  // VTK's Reset Camera frames the finite points only (a cell with a point at infinity).
  v.Mapper->SetInputData(Cube());
  const RGBImage framed = rmtest::ResetCameraImage(v.Ren, v.Win);
  auto atInfinity = Cube();
  const vtkIdType far =
    atInfinity->GetPoints()->InsertNextPoint(0, std::numeric_limits<double>::infinity(), 0);
  for (const char* name : { "s", "is" })
  {
    atInfinity->GetPointData()->GetArray(name)->InsertNextTuple1(0.5);
  }
  atInfinity->GetPointData()->GetArray("s3")->InsertNextTuple3(0.5, 0.5, 0.25);
  const vtkIdType cell[4] = { 0, 1, 2, far };
  atInfinity->InsertNextCell(VTK_TETRA, 4, cell);
  atInfinity->GetCellData()->GetArray("c")->InsertNextTuple1(0.5);
  v.Mapper->SetInputData(atInfinity);
  log.SameImage(rmtest::ResetCameraImage(v.Ren, v.Win), framed,
    "Reset Camera with a point at infinity");
  log.Warned(1, "NaN or infinite point coordinate", "Reset Camera with a point at infinity");
  log.ValidFrame("Reset Camera with a point at infinity");

  // Cell scalars: a NaN cell scalar skips its cell.
  v.Mapper->SetScalarModeToUseCellFieldData();
  v.Mapper->SelectScalarArray("c");
  const RGBImage cellPicture = v.Show(Cube());
  log.Silent("cell scalars");
  auto nanCell = Cube();
  const vtkIdType extra[4] = { 0, 1, 2, 4 };
  nanCell->InsertNextCell(VTK_TETRA, 4, extra);
  nanCell->GetCellData()->GetArray("c")->InsertNextTuple1(std::nan(""));
  log.SameImage(v.Show(nanCell), cellPicture, "a NaN cell scalar");
  log.Warned(1, "NaN or infinite scalar ('c')", "a NaN cell scalar");
  log.ValidFrame("a NaN cell scalar");

  // Integer and 3-component point scalars.
  v.Mapper->SetScalarModeToUsePointFieldData();
  v.Mapper->SelectScalarArray("s");
  auto kinds = Cube();
  vtkNew<vtkDoubleArray> ds;
  ds->SetName("ds");
  for (vtkIdType i = 0; i < 8; ++i)
  {
    ds->InsertNextValue(kinds->GetPointData()->GetArray("is")->GetComponent(i, 0));
  }
  kinds->GetPointData()->AddArray(ds);
  v.Mapper->SelectScalarArray("ds");
  const RGBImage doubles = v.Show(kinds);
  v.Mapper->SelectScalarArray("is");
  log.SameImage(v.Show(kinds), doubles, "integer point scalars");
  log.Silent("integer point scalars");
  log.ValidFrame("integer point scalars");
  v.Mapper->SelectScalarArray("s3");
  log.SameImage(v.Show(kinds), reference, "3-component point scalars: the first component");
  log.Warned(1, "scalar array 's3' has 3 components that differ: the first is used",
    "3-component point scalars");
  v.Mapper->SetScalarModeToDefault();
  log.SameImage(v.Show(Cube()), reference, "the cube again (its active scalars)");
  log.Silent("the cube again");

  // A duplicated cell overlaps its original: one warning naming the overlap, a valid frame
  // (what it shows there is undefined).
  auto overlapping = Cube();
  vtkNew<vtkIdList> firstCell;
  overlapping->GetCellPoints(0, firstCell);
  overlapping->InsertNextCell(overlapping->GetCellType(0), firstCell);
  log.Check(Lit(v.Show(overlapping)) > 1000, "a duplicated cell: the cube still drawn");
  log.Warned(1, "overlap", "a duplicated cell");
  log.ValidFrame("a duplicated cell");

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
  v.Show(prisms);
  log.Warned(1, "types the sweep does not render", "PentaHexa.vtk's prisms");
  log.Check(v.Events.Last.find("vtkPentagonalPrism") != std::string::npos &&
      v.Events.Last.find("vtkHexagonalPrism") != std::string::npos,
    "PentaHexa.vtk's prisms: the warning names both types");
  v.Show(Cube());
}

void Properties(Viewer& v)
{
  rmtest::BadInputLog& log = v.Log;
  vtkZSweepVolumeMapper* m = v.Mapper;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const auto render = [&] { return v.Render(); };
  auto nothing = [] {};
  rmtest::CheckNaNCases(log, render,
    { { "TerminationOpacity", [&] { m->SetTerminationOpacity(0.5); },
        [&] { m->SetTerminationOpacity(nan); }, [&] { m->SetTerminationOpacity(1); } },
      { "FrameBudget", nothing, [&] { m->SetFrameBudget(nan); }, nothing },
      { "CurvedTolerance", nothing, [&] { m->SetCurvedTolerance(nan); }, nothing } });
  rmtest::CheckClampCases(log, render,
    { { "TerminationOpacity", [&](double x) { m->SetTerminationOpacity(x); }, -2, 0,
        "TerminationOpacity -2 is outside [0, 1]: clamped to 0" },
      { "Integrator", [&](double x) { m->SetTerminationOpacity(1), m->SetIntegrator(static_cast<int>(x)); },
        7, VTK_ZSWEEP_INTEGRATOR_MIDPOINT, "Integrator 7 is outside [0, 2]" },
      { "TileSize", [&](double x) { m->SetIntegrator(0), m->SetTileSize(static_cast<int>(x)); },
        1, 8, "TileSize 1 is outside [8, 1024]" },
      { "ListThreshold", [&](double x) { m->SetTileSize(32), m->SetListThreshold(static_cast<int>(x)); },
        1e6, 4096, "ListThreshold 1000000 is outside [2, 4096]" },
      { "Subsampling", [&](double x) { m->SetListThreshold(16), m->SetSubsampling(static_cast<int>(x)); },
        -4, 0, "Subsampling -4 is outside [0, 9]" },
      { "FrameBudget", [&](double x) { m->SetFrameBudget(x); }, -1, 0,
        "FrameBudget -1 is outside" },
      { "CellField", [&](double x) { m->SetFrameBudget(0), m->SetCellField(static_cast<int>(x)); },
        5, VTK_ZSWEEP_CELL_FIELD_SPLIT_FACES, "CellField 5 is outside [0, 1]" },
      { "CurvedTolerance", [&](double x) { m->SetCellField(0), m->SetCurvedTolerance(x); }, 0.5,
        0.1, "CurvedTolerance 0.5 is outside" } });
  m->SetCurvedTolerance(1e-4);
  v.Render();
  log.Silent("the properties restored");
}
}

int TestZSweepBadInput(int argc, char* argv[])
{
  Viewer v;
  const RGBImage reference = v.Show(Cube());
  v.Log.Silent("the cube");
  v.Log.ValidFrame("the cube");
  v.Log.Check(Lit(reference) > 1000, "the cube is drawn");
  Cells(v, reference, argc, argv);
  Properties(v);
  v.Log.SameImage(v.Show(Cube()), reference, "everything restored");
  rmtest::CheckDegenerateCameras(v.Log, v.Ren->GetActiveCamera(), [&] { return v.Render(); },
    reference, { 0, 0, 0 });
  return v.Log.Ok ? EXIT_SUCCESS : EXIT_FAILURE;
}
