#include "vtkZSweepVolumeMapper.h"
#include "vtkRayMapperSelectionPass.h"
#include "vtkRayMapperPointArrays.h"

#include "Mappers/Common/Frame.h"
#include "Mappers/ZSweep/OpticalModel.h"
#include "Mappers/Common/RenderStatistics.h"
#include "Mappers/ZSweep/ZSweepMesh.h"
#include "Mappers/ZSweep/ZSweepRenderer.h"
#include "vtkRayMapperCore.h"
#include "vtkRayMapperRenderHelpers.h"
#include "vtkRayMapperScalarArray.h"

#include "vtkAlgorithm.h"
#include "vtkCellArray.h"
#include "vtkCellType.h"
#include "vtkCellTypes.h"
#include "vtkColorTransferFunction.h"
#include "vtkDataArray.h"
#include "vtkIdList.h"
#include "vtkObjectFactory.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPoints.h"
#include "vtkRenderer.h"
#include "vtkUnstructuredGrid.h"
#include "vtkUnstructuredGridBase.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkZSweepVolumeMapper);

struct vtkZSweepVolumeMapper::Internals
{
  vtkRayMapperCore Core;
  raymappers::ZSweepMesh Mesh;
  raymappers::ZSweepEventOrder Order; // the last frame's event order, the next sort's start
  // The mesh is built from the grid, the scalar array chosen (and its MTime), whether it is
  // cell data, Sparsification, and whether the curved cells are kept (CellField NATIVE).
  vtkRayMapperStamp<vtkDataArray*, vtkMTimeType, int, bool, bool> MeshStamp;
  vtkMTimeType ReportedNoScalarsTime = 0;
};

namespace
{
// The optical model of component 0 of a volume property: the color and opacity functions'
// nodes (their union), refined where VTK does not interpolate linearly between nodes (color
// spaces other than RGB, midpoints and sharpness) so that the piecewise-linear model follows
// what VTK's own mappers show.
raymappers::OpticalModel buildOptics(vtkVolumeProperty* property, double lo, double hi)
{
  vtkPiecewiseFunction* opacity = property->GetScalarOpacity(0);
  const bool rgb = property->GetColorChannels(0) == 3;
  vtkColorTransferFunction* color = rgb ? property->GetRGBTransferFunction(0) : nullptr;
  vtkPiecewiseFunction* gray = rgb ? nullptr : property->GetGrayTransferFunction(0);

  std::set<double> positions;
  bool refine = false;
  double node[6];
  for (int i = 0; i < opacity->GetSize(); ++i)
  {
    opacity->GetNodeValue(i, node);
    positions.insert(node[0]);
    refine = refine || node[2] != 0.5 || node[3] != 0.0;
  }
  if (color)
  {
    refine = refine || color->GetColorSpace() != VTK_CTF_RGB;
    for (int i = 0; i < color->GetSize(); ++i)
    {
      color->GetNodeValue(i, node);
      positions.insert(node[0]);
      refine = refine || node[4] != 0.5 || node[5] != 0.0;
    }
  }
  else
  {
    for (int i = 0; i < gray->GetSize(); ++i)
    {
      gray->GetNodeValue(i, node);
      positions.insert(node[0]);
      refine = refine || node[2] != 0.5 || node[3] != 0.0;
    }
  }
  if (positions.empty())
  {
    positions = { lo, hi };
  }
  std::vector<double> s(positions.begin(), positions.end());
  if (refine && s.size() > 1)
  {
    constexpr int Steps = 16;
    std::vector<double> fine;
    for (std::size_t k = 0; k + 1 < s.size(); ++k)
    {
      for (int q = 0; q < Steps; ++q)
      {
        fine.push_back(s[k] + (s[k + 1] - s[k]) * q / Steps);
      }
    }
    fine.push_back(s.back());
    s = fine;
  }
  std::vector<double> colors(3 * s.size()), alphas(s.size());
  for (std::size_t k = 0; k < s.size(); ++k)
  {
    if (color)
    {
      color->GetColor(s[k], &colors[3 * k]);
    }
    else
    {
      colors[3 * k] = colors[3 * k + 1] = colors[3 * k + 2] = gray->GetValue(s[k]);
    }
    alphas[k] = opacity->GetValue(s[k]);
  }
  raymappers::OpticalModel optics;
  optics.assign(s, colors, alphas, property->GetScalarOpacityUnitDistance(0));
  return optics;
}
}

namespace
{
// "2 vtkTriangle, 1 vtkPolyhedron": the counts of the skipped cell types, by VTK's names.
std::string SkippedTypesText(const std::map<int, std::size_t>& counts)
{
  std::ostringstream text;
  for (auto it = counts.begin(); it != counts.end(); ++it)
  {
    const char* name = vtkCellTypes::GetClassNameFromTypeId(it->first);
    text << (it == counts.begin() ? "" : ", ") << it->second << " "
         << (name && *name ? name : "cells of type ")
         << (name && *name ? "" : std::to_string(it->first));
  }
  return text.str();
}

// The sweep's kind of a VTK cell type; false for the types it does not render.
bool SweepCellType(int type, raymappers::ZSweepCellType& kind)
{
  switch (type)
  {
    case VTK_TETRA:
      kind = raymappers::ZSweepCellType::Tetra;
      return true;
    case VTK_HEXAHEDRON:
    case VTK_VOXEL:
      kind = raymappers::ZSweepCellType::Hexahedron;
      return true;
    case VTK_WEDGE:
      kind = raymappers::ZSweepCellType::Wedge;
      return true;
    case VTK_PYRAMID:
      kind = raymappers::ZSweepCellType::Pyramid;
      return true;
    default:
      return false;
  }
}

// The grid's points into the kernel's grid (double, as VTK gives them).
void CopyPoints(vtkUnstructuredGridBase* input, raymappers::ZSweepGrid& grid)
{
  if (input->GetPoints() && input->GetPoints()->GetDataType() == VTK_FLOAT)
  {
    grid.pointEpsilon = std::numeric_limits<float>::epsilon() / 2;
  }
  const vtkIdType numPoints = input->GetNumberOfPoints();
  grid.points.resize(static_cast<std::size_t>(numPoints));
  double x[3];
  for (vtkIdType i = 0; i < numPoints; ++i)
  {
    input->GetPoint(i, x);
    grid.points[static_cast<std::size_t>(i)] = raymappers::Vec3d(x[0], x[1], x[2]);
  }
}

// The cells the sweep renders into the kernel's grid (a voxel's points reordered as a
// hexahedron's); returns their ids, and counts the skipped ones by type in `skippedTypes`.
std::vector<vtkIdType> CopyCells(vtkUnstructuredGridBase* input,
  raymappers::ZSweepGrid& grid,
  std::map<int, std::size_t>& skippedTypes)
{
  const vtkIdType numCells = input->GetNumberOfCells();
  // The sizes reserved up front: grown by push_back, the arrays would hold up to twice their
  // bytes (and three times while one is moved) at the build's peak.
  const auto cells = static_cast<std::size_t>(numCells);
  grid.cellTypes.reserve(cells);
  grid.cellOffsets.reserve(cells + 1);
  if (auto* ug = vtkUnstructuredGrid::SafeDownCast(input))
  {
    grid.connectivity.reserve(
      static_cast<std::size_t>(ug->GetCells()->GetNumberOfConnectivityIds()));
  }
  grid.cellOffsets.push_back(0);
  vtkNew<vtkIdList> ids;
  std::vector<vtkIdType> keptCells;
  keptCells.reserve(cells);
  for (vtkIdType c = 0; c < numCells; ++c)
  {
    const int type = input->GetCellType(c);
    raymappers::ZSweepCellType zt;
    if (!SweepCellType(type, zt))
    {
      ++skippedTypes[type];
      continue;
    }
    input->GetCellPoints(c, ids);
    const vtkIdType n = ids->GetNumberOfIds();
    if (type == VTK_VOXEL && n == 8)
    {
      // A voxel's points go in x-fastest order; the hexahedron's go around each face.
      const vtkIdType order[8] = { 0, 1, 3, 2, 4, 5, 7, 6 };
      for (const vtkIdType k : order)
      {
        grid.connectivity.push_back(ids->GetId(k));
      }
    }
    else
    {
      for (vtkIdType k = 0; k < n; ++k)
      {
        grid.connectivity.push_back(ids->GetId(k));
      }
    }
    grid.cellTypes.push_back(zt);
    grid.cellOffsets.push_back(static_cast<std::int64_t>(grid.connectivity.size()));
    keptCells.push_back(c);
  }
  return keptCells;
}

// The scalar of each kept cell (cell data) or of each point (point data): the first
// component; NaN where the array is shorter than the grid (the mesh skips those cells).
void CopyScalars(vtkDataArray* scalars,
  const std::vector<vtkIdType>& keptCells,
  vtkIdType numPoints,
  raymappers::ZSweepGrid& grid)
{
  const vtkRayMapperPointArrays::TupleReader reader(scalars);
  if (grid.cellScalars)
  {
    grid.scalars.resize(keptCells.size());
    for (std::size_t k = 0; k < keptCells.size(); ++k)
    {
      grid.scalars[k] = static_cast<vtkIdType>(keptCells[k]) < scalars->GetNumberOfTuples()
                          ? reader.get(static_cast<std::size_t>(keptCells[k]), 0)
                          : std::nan("");
    }
  }
  else
  {
    grid.scalars.resize(static_cast<std::size_t>(numPoints));
    const vtkIdType available = std::min(numPoints, scalars->GetNumberOfTuples());
    for (vtkIdType i = 0; i < numPoints; ++i)
    {
      grid.scalars[static_cast<std::size_t>(i)] =
        i < available ? reader.get(static_cast<std::size_t>(i), 0) : std::nan("");
    }
  }
}

// One warning for each kind of cell the mesh left out.
void WarnAboutSkippedCells(vtkObject* self,
  const std::map<int, std::size_t>& skippedTypes,
  const raymappers::ZSweepMesh::Counts& counts,
  vtkDataArray* scalars)
{
  if (!skippedTypes.empty())
  {
    vtkWarningWithObjectMacro(self,
      << "cells of types the sweep does not render were skipped (" << SkippedTypesText(skippedTypes)
      << "); tetrahedra, hexahedra, voxels, wedges and pyramids are rendered.");
  }
  if (counts.badIndex)
  {
    vtkWarningWithObjectMacro(
      self, << counts.badIndex << " cells with a point index out of range were skipped.");
  }
  if (counts.nonFinitePoint)
  {
    vtkWarningWithObjectMacro(self,
      << counts.nonFinitePoint << " cells with a NaN or infinite point coordinate were skipped.");
  }
  if (counts.nonFiniteScalar)
  {
    vtkWarningWithObjectMacro(self,
      << counts.nonFiniteScalar << " cells with a NaN or infinite scalar ('"
      << (scalars->GetName() ? scalars->GetName() : "") << "') were skipped.");
  }
  if (counts.zeroVolume)
  {
    vtkWarningWithObjectMacro(self,
      << counts.zeroVolume
      << " cells of zero volume (flat, collapsed or with repeated points: flat to "
         "the precision of their points' coordinates, or a volume of at most "
      << raymappers::ZSweepMesh::ZeroVolumeRatio
      << " of their bounding box's diagonal cubed) were skipped.");
  }
  if (counts.nonManifoldTriangles)
  {
    vtkWarningWithObjectMacro(self,
      << counts.nonManifoldTriangles
      << " faces are shared by more than two cells, or by two cells on the same "
         "side: cells overlap (duplicated or intersecting cells), and the picture "
         "is undefined where they do.");
  }
}
}

vtkZSweepVolumeMapper::vtkZSweepVolumeMapper()
  : Impl(new Internals)
{
}

vtkZSweepVolumeMapper::~vtkZSweepVolumeMapper() = default;

vtkRayMapperStatistics* vtkZSweepVolumeMapper::GetStatistics()
{
  return Impl->Core.GetStatistics();
}

void vtkZSweepVolumeMapper::GetLastFrame(double frame[2])
{
  Impl->Core.GetLastFrame(frame);
}

void vtkZSweepVolumeMapper::SetLastFrame(const double frame[2])
{
  Impl->Core.SetLastFrame(frame);
}

double* vtkZSweepVolumeMapper::GetBounds()
{
  vtkUnstructuredGridBase* input = this->GetInput();
  if (!input)
  {
    return this->Superclass::GetBounds();
  }
  // vtkAbstractVolumeMapper's bounds, of the finite points only.
  if (vtkAlgorithm* producer = this->GetInputAlgorithm())
  {
    producer->Update();
  }
  vtkRayMapperPointArrays::FiniteBounds(input, this->Bounds);
  if (input->GetNumberOfCells() == 0 || input->GetNumberOfPoints() == 0)
  {
    Impl->Core.WarnEmptyInput(this, input, "cells", "volume");
  }
  return this->Bounds;
}

void vtkZSweepVolumeMapper::ReleaseGraphicsResources(vtkWindow* win)
{
  Impl->Core.ReleaseGraphicsResources(win);
}

bool vtkZSweepVolumeMapper::UpdateMesh(vtkUnstructuredGridBase* input)
{
  int cellFlag = 0;
  vtkDataArray* scalars = vtkAbstractMapper::GetScalars(
    input, this->ScalarMode, this->ArrayAccessMode, this->ArrayId, this->ArrayName, cellFlag);
  if (!scalars || scalars->GetNumberOfTuples() == 0)
  {
    // Once per input and selection, not on every render.
    if (Impl->ReportedNoScalarsTime < std::max(input->GetMTime(), this->GetMTime()))
    {
      vtkErrorMacro(<< "The input has no scalars to render: give it point or cell scalars, or "
                       "choose an array with SelectScalarArray and SetScalarMode.");
      Impl->ReportedNoScalarsTime = std::max(input->GetMTime(), this->GetMTime());
    }
    Impl->MeshStamp.Invalidate();
    return false;
  }
  const bool native = this->CellField == VTK_ZSWEEP_CELL_FIELD_NATIVE;
  if (!Impl->MeshStamp.Changed(
        this, input, { scalars, scalars->GetMTime(), cellFlag, this->Sparsification, native }))
  {
    return true;
  }

  raymappers::ZSweepGrid grid;
  grid.cellScalars = cellFlag == 1;
  CopyPoints(input, grid);
  std::map<int, std::size_t> skippedTypes; // cells of types the sweep does not render
  const std::vector<vtkIdType> keptCells = CopyCells(input, grid, skippedTypes);
  vtkRayMapperWarnIfComponentsDiffer(this, scalars, "scalar");
  CopyScalars(scalars, keptCells, input->GetNumberOfPoints(), grid);
  Impl->Mesh.build(grid, this->Sparsification, native);
  Impl->Core.CountBuild();
  WarnAboutSkippedCells(this, skippedTypes, Impl->Mesh.counts(), scalars);
  return true;
}

raymappers::ZSweepParameters vtkZSweepVolumeMapper::GatherParameters() const
{
  raymappers::ZSweepParameters params;
  params.integrator = this->Integrator == VTK_ZSWEEP_INTEGRATOR_FARIAS
    ? raymappers::ZSweepIntegrator::Farias
    : (this->Integrator == VTK_ZSWEEP_INTEGRATOR_MIDPOINT ? raymappers::ZSweepIntegrator::Midpoint
                                                          : raymappers::ZSweepIntegrator::Exact);
  params.cellField = this->CellField == VTK_ZSWEEP_CELL_FIELD_SPLIT_FACES
    ? raymappers::ZSweepCellField::SplitFaces
    : raymappers::ZSweepCellField::Native;
  params.curvedTolerance = this->CurvedTolerance;
  params.tileSize = this->TileSize;
  params.listThreshold = this->ListThreshold;
  params.terminationOpacity = this->TerminationOpacity;
  return params;
}

void vtkZSweepVolumeMapper::Render(vtkRenderer* ren, vtkVolume* vol)
{
  if (vtkRayMapperSelectionPass::Of(ren))
  {
    // A hardware selection pass: selects nothing, hides what is behind.
    Impl->Core.PresentSelectionFootprint(ren);
    return;
  }
  Impl->Core.Execute(this, this->NumberOfThreads, [&] { this->RenderFrame(ren, vol); },
    [this]
    {
      Impl->Mesh = raymappers::ZSweepMesh();
      Impl->Order = raymappers::ZSweepEventOrder();
      Impl->MeshStamp.Invalidate();
    });
}

void vtkZSweepVolumeMapper::RenderFrame(vtkRenderer* ren, vtkVolume* vol)
{
  raymappers::RenderStatistics stats;
  vtkUnstructuredGridBase* input = this->GetInput();
  vtkRayMapperView view;
  if (!input || input->GetNumberOfCells() == 0 || input->GetNumberOfPoints() == 0)
  {
    Impl->Core.Skip(stats);
    return;
  }
  bool haveMesh = false;
  {
    raymappers::ScopedPhase phase(stats, "mesh");
    haveMesh = this->UpdateMesh(input);
  }
  if (!haveMesh)
  {
    Impl->Core.Skip(stats);
    return;
  }
  Impl->Core.AddBuildCounters(stats);
  stats.addCounter("cells", static_cast<std::int64_t>(Impl->Mesh.counts().cellsUsed));
  stats.addCounter("mesh_bytes", static_cast<std::int64_t>(Impl->Mesh.memoryBytes()));
  stats.addCounter("kept_cells", static_cast<std::int64_t>(Impl->Mesh.counts().cellsKept));
  stats.addCounter("inverted_cells", static_cast<std::int64_t>(Impl->Mesh.counts().inverted));
  const raymappers::OpticalModel optics =
    buildOptics(vol->GetProperty(), Impl->Mesh.scalarMin(), Impl->Mesh.scalarMax());
  if (!Impl->Core.GatherView(this, ren, vol, view))
  {
    Impl->Core.Skip(stats);
    return;
  }
  // Time-critical rendering: rays d pixels apart, the image enlarged.
  const double d =
    Impl->Core.BeginFrame(ren, vtkRayMapperSampleDistances::Of(this), stats);
  stats.addCounter("subsampling", static_cast<std::int64_t>(std::ceil(d)));
  const raymappers::View kernelView =
    Impl->Core.KernelView(ren, view, d, Impl->Mesh.origin(), true, stats);
  raymappers::renderZSweep({ Impl->Mesh, optics, &Impl->Order }, kernelView,
    this->GatherParameters(), Impl->Core.Target(), stats);
  Impl->Core.Present(ren, view, vtkRayMapperFrameDrawer::Mode::BlendPremultiplied, false, stats);
}

void vtkZSweepVolumeMapper::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Integrator: " << this->Integrator << "\n";
  os << indent << "CellField: " << this->CellField << "\n";
  os << indent << "CurvedTolerance: " << this->CurvedTolerance << "\n";
  os << indent << "TileSize: " << this->TileSize << "\n";
  os << indent << "NumberOfThreads: " << this->NumberOfThreads << "\n";
  os << indent << "ListThreshold: " << this->ListThreshold << "\n";
  os << indent << "TerminationOpacity: " << this->TerminationOpacity << "\n";
  vtkRayMapperSampleDistances::Of(this).Print(os, indent);
  os << indent << "Sparsification: " << this->Sparsification << "\n";
}
