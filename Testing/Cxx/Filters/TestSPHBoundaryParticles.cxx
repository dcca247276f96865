// vtkSPHBoundaryParticles on a block of 20 x 18 x 16 particles at spacing 1 with radius 1.04
// (the spheres cover the block): no particle deeper than three cells (3 x 2.08) inside the
// block's faces is kept, every particle of the outermost layer is, the kept particles carry
// their point data (an id array matches their coordinates), the counts in the field data add
// up; a block whose spheres do not cover it (radius 0.4) keeps everything; bad particles are
// dropped with a warning; an empty input gives an empty output.
// Usage: TestSPHBoundaryParticles
#include "vtkSPHBoundaryParticles.h"

#include "vtkCallbackCommand.h"
#include "vtkCellArray.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <string>

namespace
{
int Failures = 0;
int Warnings = 0;

void Check(bool ok, const std::string& what)
{
  std::printf("%s %s\n", ok ? "ok  " : "FAIL", what.c_str());
  Failures += ok ? 0 : 1;
}

void CountWarnings(vtkObject*, unsigned long, void*, void*)
{
  ++Warnings;
}

constexpr int NX = 20, NY = 18, NZ = 16;

/// The block's particles with a point array "id" = their index.
vtkNew<vtkPolyData> Block()
{
  vtkNew<vtkPolyData> block;
  vtkNew<vtkPoints> points;
  vtkNew<vtkIntArray> id;
  id->SetName("id");
  for (int k = 0; k < NZ; ++k)
  {
    for (int j = 0; j < NY; ++j)
    {
      for (int i = 0; i < NX; ++i)
      {
        id->InsertNextValue(static_cast<int>(points->InsertNextPoint(i, j, k)));
      }
    }
  }
  block->SetPoints(points);
  block->GetPointData()->AddArray(id);
  return block;
}

double Field(vtkPolyData* p, const char* name)
{
  vtkDataArray* a = p->GetFieldData()->GetArray(name);
  return a ? a->GetComponent(0, 0) : -1;
}
}

int main()
{
  vtkNew<vtkPolyData> block = Block();
  const vtkIdType n = block->GetNumberOfPoints();
  vtkNew<vtkSPHBoundaryParticles> filter;
  vtkNew<vtkCallbackCommand> warnings;
  warnings->SetCallback(CountWarnings);
  filter->AddObserver(vtkCommand::WarningEvent, warnings);
  filter->SetInputData(block);
  filter->SetRadius(1.04);
  filter->Update();
  vtkPolyData* out = filter->GetOutput();
  const vtkIdType m = out->GetNumberOfPoints();
  const double s = Field(out, "CellSize");
  std::printf("%lld of %lld kept, cell size %g, culled %g, inner cells %g\n",
    static_cast<long long>(m), static_cast<long long>(n), s, Field(out, "CulledParticles"),
    Field(out, "InnerCells"));
  Check(std::abs(s - 2.08) < 1e-5, "cell size: twice the radius");
  Check(m > 0 && m < n && m + Field(out, "CulledParticles") == n,
    "inner particles culled; kept + culled = all");
  Check(out->GetNumberOfVerts() == m, "one vertex per kept particle");
  vtkDataArray* id = out->GetPointData()->GetArray("id");
  bool consistent = id && id->GetNumberOfTuples() == m;
  bool deepDropped = true;
  int outerKept = 0;
  for (vtkIdType q = 0; consistent && q < m; ++q)
  {
    const int i = static_cast<int>(id->GetComponent(q, 0));
    double p[3];
    out->GetPoint(q, p);
    consistent = p[0] == i % NX && p[1] == (i / NX) % NY && p[2] == i / (NX * NY) &&
      (q == 0 || id->GetComponent(q - 1, 0) < i);
    const double depth = std::min({ p[0], NX - 1 - p[0], p[1], NY - 1 - p[1], p[2], NZ - 1 - p[2] });
    deepDropped = deepDropped && depth <= 3 * s;
    outerKept += depth == 0 ? 1 : 0;
  }
  const int outer = NX * NY * NZ - (NX - 2) * (NY - 2) * (NZ - 2);
  Check(consistent, "kept particles in input order with their own point data");
  Check(deepDropped, "no particle deeper than three cells inside kept");
  Check(outerKept == outer, "every particle of the outermost layer kept");
  Check(Warnings == 0, "no warning");

  // Spheres that leave holes (radius 0.4 at spacing 1): no cell is full, nothing culled.
  filter->SetRadius(0.4);
  filter->Update();
  Check(filter->GetOutput()->GetNumberOfPoints() == n && Field(filter->GetOutput(), "FullCells") == 0,
    "spheres that do not cover the cells: nothing culled");

  // Bad particles dropped with a warning each kind; empty input.
  filter->SetRadius(1.04);
  vtkNew<vtkDoubleArray> radius;
  radius->SetName("r");
  radius->SetNumberOfValues(n);
  radius->Fill(1.0);
  radius->SetValue(5, -1.0);
  radius->SetValue(6, std::numeric_limits<double>::quiet_NaN());
  block->GetPointData()->AddArray(radius);
  block->GetPoints()->SetPoint(7, std::numeric_limits<double>::quiet_NaN(), 0, 0);
  block->Modified();
  filter->SetScaleArray("r");
  filter->SetScaleFactor(1.04);
  filter->Update();
  vtkDataArray* kept = filter->GetOutput()->GetPointData()->GetArray("id");
  bool badGone = kept != nullptr;
  for (vtkIdType q = 0; badGone && q < kept->GetNumberOfTuples(); ++q)
  {
    const int i = static_cast<int>(kept->GetComponent(q, 0));
    badGone = i != 5 && i != 6 && i != 7;
  }
  Check(Warnings == 2 && badGone, "NaN position and bad radii: dropped, two warnings");
  vtkNew<vtkPolyData> empty;
  empty->SetPoints(vtkNew<vtkPoints>());
  filter->SetInputData(empty);
  filter->Update();
  Check(filter->GetOutput()->GetNumberOfPoints() == 0, "empty input: empty output");

  std::printf("%s\n", Failures == 0 ? "PASSED" : "FAILED");
  return Failures == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
