#include "vtkRayMapperGatherPoints.h"
#include "vtkRayMapperPointArrays.h"


#include "vtkCompositeDataSet.h"
#include "vtkDataArray.h"
#include "vtkDataSet.h"
#include "vtkDataSetAttributes.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPointSet.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkUnsignedCharArray.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace
{
// A point that a ghost array marks as a copy of a point owned elsewhere, or as hidden,
// is not drawn (in parallel its owner draws it).
constexpr unsigned char SkippedGhostPoint =
  vtkDataSetAttributes::DUPLICATEPOINT | vtkDataSetAttributes::HIDDENPOINT;

bool HasSkippedGhostPoints(vtkDataSet* ds)
{
  vtkUnsignedCharArray* ghosts = ds->GetPointGhostArray();
  if (!ghosts)
  {
    return false;
  }
  const vtkIdType n = ghosts->GetNumberOfValues();
  for (vtkIdType i = 0; i < n; ++i)
  {
    if (ghosts->GetValue(i) & SkippedGhostPoint)
    {
      return true;
    }
  }
  return false;
}
}

//----------------------------------------------------------------------------
vtkSmartPointer<vtkPolyData> vtkRayMapperGatherPoints(vtkDataObject* input)
{
  auto output = vtkSmartPointer<vtkPolyData>::New();
  if (!input)
  {
    output->SetPoints(vtkSmartPointer<vtkPoints>::New());
    return output;
  }

  std::vector<vtkDataSet*> leaves;
  for (vtkDataSet* ds : vtkCompositeDataSet::GetDataSets<vtkDataSet>(input))
  {
    if (ds && ds->GetNumberOfPoints() > 0)
    {
      leaves.push_back(ds);
    }
  }
  if (leaves.empty())
  {
    output->SetPoints(vtkSmartPointer<vtkPoints>::New());
    return output;
  }

  // Fast path: one point set without ghost points to drop: share its points and arrays.
  if (leaves.size() == 1)
  {
    vtkPointSet* ps = vtkPointSet::SafeDownCast(leaves[0]);
    if (ps && ps->GetPoints() && !HasSkippedGhostPoints(ps))
    {
      output->SetPoints(ps->GetPoints());
      output->GetPointData()->ShallowCopy(ps->GetPointData());
      return output;
    }
  }

  // General path: copy the points of every leaf, and the point arrays all leaves share.
  vtkDataSetAttributes::FieldList fieldList;
  vtkIdType total = 0;
  int pointsType = -1;
  for (vtkDataSet* ds : leaves)
  {
    fieldList.IntersectFieldList(ds->GetPointData());
    total += ds->GetNumberOfPoints();
    vtkPointSet* ps = vtkPointSet::SafeDownCast(ds);
    const int type = (ps && ps->GetPoints()) ? ps->GetPoints()->GetDataType() : VTK_DOUBLE;
    pointsType = (pointsType == -1 || pointsType == type) ? type : VTK_DOUBLE;
  }

  vtkNew<vtkPoints> points;
  points->SetDataType(pointsType);
  points->SetNumberOfPoints(total);
  vtkPointData* outPD = output->GetPointData();
  outPD->CopyAllocate(fieldList, total);

  vtkIdType next = 0;
  for (int leaf = 0; leaf < static_cast<int>(leaves.size()); ++leaf)
  {
    vtkDataSet* ds = leaves[leaf];
    const vtkIdType n = ds->GetNumberOfPoints();
    vtkPointData* inPD = ds->GetPointData();
    vtkPointSet* ps = vtkPointSet::SafeDownCast(ds);
    if (!HasSkippedGhostPoints(ds))
    {
      if (ps && ps->GetPoints())
      {
        points->InsertPoints(next, n, 0, ps->GetPoints());
      }
      else
      {
        double x[3];
        for (vtkIdType i = 0; i < n; ++i)
        {
          ds->GetPoint(i, x);
          points->SetPoint(next + i, x);
        }
      }
      outPD->CopyData(fieldList, inPD, leaf, next, n, 0);
      next += n;
    }
    else
    {
      vtkUnsignedCharArray* ghosts = ds->GetPointGhostArray();
      double x[3];
      for (vtkIdType i = 0; i < n; ++i)
      {
        if (ghosts->GetValue(i) & SkippedGhostPoint)
        {
          continue;
        }
        ds->GetPoint(i, x);
        points->SetPoint(next, x);
        outPD->CopyData(fieldList, inPD, leaf, i, next);
        ++next;
      }
    }
  }
  if (next < total)
  {
    points->SetNumberOfPoints(next);
  }
  // The ghost array of the inputs says nothing about the gathered points.
  outPD->RemoveArray(vtkDataSetAttributes::GhostArrayName());
  output->SetPoints(points);
  return output;
}

vtkSmartPointer<vtkPolyData> vtkRayMapperDeliveredPoints(vtkDataObject* piece)
{
  if (auto* points = vtkPolyData::SafeDownCast(piece))
  {
    return points;
  }
  return vtkRayMapperGatherPoints(piece);
}

double vtkRayMapperLargestRadius(vtkPolyData* points,
  const char* radiusArray,
  double radius,
  double scale)
{
  vtkDataArray* array =
    points && radiusArray ? points->GetPointData()->GetArray(radiusArray) : nullptr;
  if (array && array->GetNumberOfTuples() > 0)
  {
    // The largest radius a particle is drawn with (huge ones are skipped), so that one
    // skipped radius of 1e300 does not make the view's bounds huge.
    return vtkRayMapperPointArrays::LargestParticleLength(array, std::fabs(scale));
  }
  const double r = std::fabs(radius * scale);
  return std::isfinite(r) ? r : 0.0;
}
