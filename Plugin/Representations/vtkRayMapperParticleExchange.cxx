#include "vtkRayMapperParticleExchange.h"

#include "vtkIdTypeArray.h"
#include "vtkMultiBlockDataSet.h"
#include "vtkMultiProcessController.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkRayMapperGatherPoints.h"
#include "vtkUnsignedIntArray.h"

#include <algorithm>
#include <cmath>

const char* const vtkRayMapperOriginIdsName = "vtkRayMapperOriginIds";
const char* const vtkRayMapperOriginProcessesName = "vtkRayMapperOriginProcesses";

namespace
{
/// Squared distance from x to the box (0 inside).
double squaredDistance(const double x[3], const double b[6])
{
  double d2 = 0.0;
  for (int a = 0; a < 3; ++a)
  {
    const double below = b[2 * a] - x[a], above = x[a] - b[2 * a + 1];
    const double e = below > 0.0 ? below : (above > 0.0 ? above : 0.0);
    d2 += e * e;
  }
  return d2;
}

/// The particles of `points` for which `keep(x)` holds, with their point arrays.
template<typename Keep>
vtkSmartPointer<vtkPolyData> selectParticles(vtkPolyData* points, Keep keep)
{
  auto out = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> kept;
  kept->SetDataType(points->GetPoints() ? points->GetPoints()->GetDataType() : VTK_FLOAT);
  vtkPointData* inPD = points->GetPointData();
  vtkPointData* outPD = out->GetPointData();
  outPD->CopyAllocate(inPD);
  double x[3];
  const vtkIdType n = points->GetNumberOfPoints();
  for (vtkIdType i = 0; i < n; ++i)
  {
    points->GetPoint(i, x);
    if (keep(x))
    {
      outPD->CopyData(inPD, i, kept->InsertNextPoint(x));
    }
  }
  out->SetPoints(kept);
  return out;
}

/// One point set of several (GatherPoints keeps the arrays they share).
vtkSmartPointer<vtkPolyData> concatenate(const std::vector<vtkSmartPointer<vtkDataObject>>& parts)
{
  vtkNew<vtkMultiBlockDataSet> blocks;
  blocks->SetNumberOfBlocks(static_cast<unsigned int>(parts.size()));
  for (unsigned int i = 0; i < parts.size(); ++i)
  {
    blocks->SetBlock(i, parts[i]);
  }
  return vtkRayMapperGatherPoints(blocks);
}
}

//----------------------------------------------------------------------------
void vtkRayMapperRegionOf(const std::vector<vtkBoundingBox>& cuts, int rank, double bounds[6])
{
  vtkBoundingBox all;
  for (const vtkBoundingBox& cut : cuts)
  {
    all.AddBox(cut);
  }
  double whole[6];
  all.GetBounds(whole);
  cuts[rank].GetBounds(bounds);
  for (int f = 0; f < 6; ++f)
  {
    if (bounds[f] == whole[f])
    {
      bounds[f] = (f % 2 == 0) ? -VTK_DOUBLE_MAX : VTK_DOUBLE_MAX;
    }
  }
}

//----------------------------------------------------------------------------
vtkSmartPointer<vtkPolyData> vtkRayMapperDistributeParticles(vtkPolyData* local,
  const std::vector<vtkBoundingBox>& cuts,
  double margin,
  vtkMultiProcessController* controller,
  long long& ghosts)
{
  const int rank = controller->GetLocalProcessId();
  const int ranks = static_cast<int>(cuts.size());
  std::vector<std::vector<double>> regions(ranks, std::vector<double>(6));
  for (int r = 0; r < ranks; ++r)
  {
    vtkRayMapperRegionOf(cuts, r, regions[r].data());
  }
  const double m2 = margin * margin;
  auto reaches = [&](int r) {
    return [&, r](const double x[3]) { return squaredDistance(x, regions[r].data()) <= m2; };
  };

  // Pairwise exchange, the lower rank of a pair sending first: every process sends each
  // other one the particles whose support meets that one's region.
  constexpr int Tag = 5871;
  std::vector<vtkSmartPointer<vtkDataObject>> parts(ranks);
  parts[rank] = selectParticles(local, reaches(rank));
  for (int r = 0; r < ranks; ++r)
  {
    if (r == rank)
    {
      continue;
    }
    vtkSmartPointer<vtkPolyData> outgoing = selectParticles(local, reaches(r));
    if (rank < r)
    {
      controller->Send(outgoing, r, Tag);
      parts[r] = vtkSmartPointer<vtkDataObject>::Take(controller->ReceiveDataObject(r, Tag));
    }
    else
    {
      parts[r] = vtkSmartPointer<vtkDataObject>::Take(controller->ReceiveDataObject(r, Tag));
      controller->Send(outgoing, r, Tag);
    }
  }

  // Ghosts: the received particles whose centre lies outside this region.
  ghosts = 0;
  const double* own = regions[rank].data();
  for (int r = 0; r < ranks; ++r)
  {
    auto* theirs = vtkPolyData::SafeDownCast(parts[r]);
    const vtkIdType n = r == rank || !theirs ? 0 : theirs->GetNumberOfPoints();
    double x[3];
    for (vtkIdType i = 0; i < n; ++i)
    {
      theirs->GetPoint(i, x);
      ghosts += squaredDistance(x, own) > 0.0;
    }
  }
  return concatenate(parts);
}

//----------------------------------------------------------------------------
vtkSmartPointer<vtkPolyData> vtkRayMapperGatherParticlesToFirst(vtkPolyData* local,
  vtkMultiProcessController* controller)
{
  std::vector<vtkSmartPointer<vtkDataObject>> received;
  controller->Gather(local, received, 0);
  if (controller->GetLocalProcessId() != 0)
  {
    return vtkRayMapperGatherPoints(nullptr);
  }
  return concatenate(received);
}

//----------------------------------------------------------------------------
vtkSmartPointer<vtkPolyData> vtkRayMapperTagOrigins(vtkPolyData* local, int rank)
{
  auto tagged = vtkSmartPointer<vtkPolyData>::New();
  tagged->ShallowCopy(local);
  const vtkIdType n = local->GetNumberOfPoints();
  vtkNew<vtkIdTypeArray> ids;
  ids->SetName(vtkRayMapperOriginIdsName);
  ids->SetNumberOfValues(n);
  vtkNew<vtkUnsignedIntArray> processes;
  processes->SetName(vtkRayMapperOriginProcessesName);
  processes->SetNumberOfValues(n);
  for (vtkIdType i = 0; i < n; ++i)
  {
    ids->SetValue(i, i);
    processes->SetValue(i, static_cast<unsigned int>(rank));
  }
  tagged->GetPointData()->AddArray(ids);
  tagged->GetPointData()->AddArray(processes);
  return tagged;
}

//----------------------------------------------------------------------------
vtkSmartPointer<vtkIdTypeArray> vtkRayMapperSelectedOfExchange(vtkIdTypeArray* own,
  vtkDataSet* piece,
  vtkMultiProcessController* controller)
{
  // Every process's selection, as (process, id) pairs flattened, sorted for the lookup.
  vtkNew<vtkIdTypeArray> mine;
  const vtkIdType count = own ? own->GetNumberOfValues() : 0;
  mine->SetNumberOfValues(2 * count);
  for (vtkIdType k = 0; k < count; ++k)
  {
    mine->SetValue(2 * k, controller->GetLocalProcessId());
    mine->SetValue(2 * k + 1, own->GetValue(k));
  }
  vtkNew<vtkIdTypeArray> all;
  controller->AllGatherV(mine, all);
  std::vector<std::pair<vtkIdType, vtkIdType>> selected(all->GetNumberOfValues() / 2);
  for (std::size_t k = 0; k < selected.size(); ++k)
  {
    selected[k] = { all->GetValue(2 * k), all->GetValue(2 * k + 1) };
  }
  std::sort(selected.begin(), selected.end());

  auto out = vtkSmartPointer<vtkIdTypeArray>::New();
  vtkPointData* pd = piece ? piece->GetPointData() : nullptr;
  auto* ids = pd ? vtkIdTypeArray::SafeDownCast(pd->GetArray(vtkRayMapperOriginIdsName)) : nullptr;
  auto* processes =
    pd ? vtkUnsignedIntArray::SafeDownCast(pd->GetArray(vtkRayMapperOriginProcessesName)) : nullptr;
  const vtkIdType n = ids && processes && !selected.empty() ? piece->GetNumberOfPoints() : 0;
  for (vtkIdType i = 0; i < n; ++i)
  {
    const std::pair<vtkIdType, vtkIdType> origin(processes->GetValue(i), ids->GetValue(i));
    if (std::binary_search(selected.begin(), selected.end(), origin))
    {
      out->InsertNextValue(i);
    }
  }
  return out;
}
