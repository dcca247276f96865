#include "vtkSPHBoundaryParticles.h"

#include "Mappers/SPH/FluidCells.h"
#include "Mappers/SPH/FluidParticles.h"
#include "Mappers/Common/ParticleInput.h"

#include "vtkRayMapperScalarArray.h"
#include "vtkCellArray.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPointSet.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"

#include <algorithm>
#include <cmath>
#include <vector>

vtkStandardNewMacro(vtkSPHBoundaryParticles);

vtkSPHBoundaryParticles::vtkSPHBoundaryParticles() = default;

vtkSPHBoundaryParticles::~vtkSPHBoundaryParticles()
{
  this->SetScaleArray(nullptr);
}

int vtkSPHBoundaryParticles::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPointSet");
  return 1;
}

namespace
{
void addCount(vtkFieldData* fd, const char* name, double value)
{
  vtkNew<vtkDoubleArray> a;
  a->SetName(name);
  a->InsertNextValue(value);
  fd->AddArray(a);
}
}

int vtkSPHBoundaryParticles::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPointSet* input = vtkPointSet::GetData(inputVector[0], 0);
  vtkPolyData* output = vtkPolyData::GetData(outputVector, 0);
  vtkPoints* points = input ? input->GetPoints() : nullptr;
  const vtkIdType n = points ? points->GetNumberOfPoints() : 0;
  if (n == 0)
  {
    vtkWarningMacro(<< "The input has no points: the output is empty.");
  }
  vtkDataArray* radii = nullptr;
  if (n > 0 && this->ScaleArray && this->ScaleArray[0])
  {
    radii = input->GetPointData()->GetArray(this->ScaleArray);
    if (!radii)
    {
      vtkWarningMacro(<< "radius array '" << this->ScaleArray
                      << "' is not a point array of the input; using the constant radius "
                      << this->Radius << ".");
    }
  }
  vtkRayMapperWarnIfComponentsDiffer(this, radii, "radius");

  // The valid spheres (their input ids kept), by the particle kernels' own rule
  // (ParticleTally::admit: finite centre, finite positive radius).
  std::vector<vtkIdType> ids;
  std::vector<raymappers::Vec3d> centers;
  std::vector<double> r;
  raymappers::ParticleTally tally;
  for (vtkIdType i = 0; i < n; ++i)
  {
    double p[3];
    points->GetPoint(i, p);
    const raymappers::Vec3d c(p[0], p[1], p[2]);
    const double ri = (radii ? radii->GetComponent(i, 0) : this->Radius) * this->ScaleFactor;
    if (tally.admit(c, true, ri) > 0.f)
    {
      ids.push_back(i);
      centers.push_back(c);
      r.push_back(ri);
    }
  }
  if (tally.nonFinite > 0)
  {
    vtkWarningMacro(<< tally.nonFinite
                    << " particles have NaN or infinite coordinates and are dropped.");
  }
  if (tally.badRadius > 0)
  {
    vtkWarningMacro(<< tally.badRadius
                    << " particles have a zero, negative, non-finite or huge (above 1e15) radius and are dropped.");
  }
  raymappers::FluidParticles particles;
  const raymappers::Vec3d origin = centers.empty() ? raymappers::Vec3d() : centers.front();
  raymappers::buildFluidParticles(
    centers.size(), origin, [&](std::size_t k) { return centers[k]; },
    [&](std::size_t k) { return r[k]; }, particles);
  raymappers::FluidCells cells;
  raymappers::buildFluidCells(particles, this->CellSize, true, cells);

  // The kept particles in input order, with their point data and a vertex each.
  std::vector<vtkIdType> kept(cells.kept.size());
  std::transform(cells.kept.begin(), cells.kept.end(), kept.begin(),
    [&](std::uint32_t k) { return ids[k]; });
  std::sort(kept.begin(), kept.end());
  const vtkIdType m = static_cast<vtkIdType>(kept.size());
  vtkNew<vtkPoints> outPoints;
  outPoints->SetDataType(points ? points->GetDataType() : VTK_FLOAT);
  outPoints->SetNumberOfPoints(m);
  vtkPointData* outPd = output->GetPointData();
  if (input)
  {
    outPd->CopyAllocate(input->GetPointData(), m);
  }
  vtkNew<vtkIdTypeArray> connectivity;
  connectivity->SetNumberOfValues(m);
  for (vtkIdType j = 0; j < m; ++j)
  {
    outPoints->SetPoint(j, points->GetPoint(kept[j]));
    outPd->CopyData(input->GetPointData(), kept[j], j);
    connectivity->SetValue(j, j);
  }
  vtkNew<vtkCellArray> verts;
  verts->SetData(1, connectivity);
  output->SetPoints(outPoints);
  output->SetVerts(verts);
  vtkFieldData* fd = output->GetFieldData();
  addCount(fd, "CellSize", cells.cellSize);
  addCount(fd, "OccupiedCells", static_cast<double>(cells.occupiedCells));
  addCount(fd, "FullCells", static_cast<double>(cells.fullCells));
  addCount(fd, "InnerCells", static_cast<double>(cells.innerCells));
  addCount(fd, "CulledParticles", static_cast<double>(cells.culledParticles));
  return 1;
}

void vtkSPHBoundaryParticles::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Radius: " << this->Radius << "\n";
  os << indent << "ScaleArray: " << (this->ScaleArray ? this->ScaleArray : "")
     << "\n";
  os << indent << "ScaleFactor: " << this->ScaleFactor << "\n";
  os << indent << "CellSize: " << this->CellSize << "\n";
}
