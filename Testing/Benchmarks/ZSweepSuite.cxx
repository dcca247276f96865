// The zsweep suite: vtkZSweepVolumeMapper (zsweep: the exact integrator, the dissertation's
// formula, the midpoint rule, tile sizes, list thresholds, time-critical subsampling p,
// native hexahedra (their trilinear field, and the split faces' linear field) and
// sparsification, the exact, sparse and native rows with build_ms the
// median mesh build of a time step) against the
// mappers a VTK or ParaView user has for unstructured grids: VTK's ZSweep
// (vtk-zsweep, vtkUnstructuredGridVolumeZSweepMapper), the Bunyk ray caster (vtk-bunyk,
// vtkUnstructuredGridVolumeRayCastMapper) and projected tetrahedra (vtk-projected-tetra,
// vtkProjectedTetrahedraMapper, on the OpenGL driver), all on the same tetrahedra and view.
// The error columns compare with an independent brute-force reference (Testing/Cxx/Kernels/
// UnstructuredReference.h: every tetrahedron a ray meets clipped in double precision, each
// segment integrated numerically), rendered over the same white background; the native rows
// of a grid of hexahedra, wedges and pyramids compare with the converged reference of their
// own fields inside their bilinear faces instead (TrilinearReference.h; rows "reference,
// trilinear;rk4;step=...", whose coarser step's row shows its convergence).
//
// Data: the Blunt Fin and the Combustion Chamber (PLOT3D, density), disk_out_ref.ex2
// (Temp) and a tetrahedralized wavelet (vtkRTAnalyticSource, extent +-20: 320,000
// tetrahedra); --data takes PLOT3D xyz files (the q file beside it), Exodus or VTK files,
// wavelet:N (the wavelet tetrahedralized, its extent chosen for about N tetrahedra) and
// hex-wavelet:N (about N hexahedra of a warped wavelet, native rows only: no tetrahedra),
// rendered by the point array --array NAME, else the reader's or active scalars, else the
// first 1-component point array.
// Three views each: far, side and close.
#include "../Cxx/Kernels/TrilinearReference.h"
#include "../Cxx/Kernels/UnstructuredReference.h"
#include "BenchData.h"
#include "BenchRun.h"
#include "vtkRayMapperStatistics.h"
#include "vtkZSweepVolumeMapper.h"

#include "vtkAppendFilter.h"
#include "vtkCamera.h"
#include "vtkCellArray.h"
#include "vtkCellType.h"
#include "vtkColorTransferFunction.h"
#include "vtkCompositeDataSet.h"
#include "vtkDataArray.h"
#include "vtkDataSet.h"
#include "vtkDataSetTriangleFilter.h"
#include "vtkExodusIIReader.h"
#include "vtkIdList.h"
#include "vtkIdTypeArray.h"
#include "vtkImageData.h"
#include "vtkMath.h"
#include "vtkMatrix4x4.h"
#include "vtkMultiBlockDataSet.h"
#include "vtkMultiBlockPLOT3DReader.h"
#include "vtkNew.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkProjectedTetrahedraMapper.h"
#include "vtkRTAnalyticSource.h"
#include "vtkRenderer.h"
#include "vtkSmartPointer.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"
#include "vtkUnstructuredGridReader.h"
#include "vtkUnstructuredGridVolumeRayCastMapper.h"
#include "vtkUnstructuredGridVolumeZSweepMapper.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"
#include "vtkXMLUnstructuredGridReader.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <sstream>

namespace bench
{

namespace
{
struct Grid
{
  std::string name;
  vtkSmartPointer<vtkUnstructuredGrid> tetra;
  vtkSmartPointer<vtkUnstructuredGrid> native; // hexahedra or voxels; null when tetrahedra
};

vtkSmartPointer<vtkUnstructuredGrid> ToUnstructured(vtkDataObject* data, bool tetrahedralize)
{
  auto out = vtkSmartPointer<vtkUnstructuredGrid>::New();
  if (tetrahedralize && !vtkCompositeDataSet::SafeDownCast(data))
  {
    // Structured grids and images split each hexahedron into 5 tetrahedra (187,395 for the
    // Blunt Fin, as in the dissertation; 320,000 for the wavelet).
    vtkNew<vtkDataSetTriangleFilter> tetra;
    tetra->SetInputData(data);
    tetra->TetrahedraOnlyOn();
    tetra->Update();
    out->ShallowCopy(tetra->GetOutput());
    return out;
  }
  vtkNew<vtkAppendFilter> append;
  if (auto* composite = vtkCompositeDataSet::SafeDownCast(data))
  {
    for (vtkDataSet* ds : vtkCompositeDataSet::GetDataSets<vtkDataSet>(composite))
    {
      append->AddInputData(ds);
    }
  }
  else
  {
    append->AddInputData(data);
  }
  append->MergePointsOn();
  append->Update();
  if (!tetrahedralize)
  {
    out->ShallowCopy(append->GetOutput());
    return out;
  }
  vtkNew<vtkDataSetTriangleFilter> tetra;
  tetra->SetInputData(append->GetOutput());
  tetra->TetrahedraOnlyOn();
  tetra->Update();
  out->ShallowCopy(tetra->GetOutput());
  return out;
}

// An array's name for the printout ("" for an unnamed one).
std::string Name(vtkDataArray* a)
{
  return a && a->GetName() ? a->GetName() : "";
}

// The scalars of the grid's point data: --array (false, with the arrays present, when the
// file has no such point array), else the reader's choice above or the active scalars, else
// the first 1-component array as the other suites colour by (FindColorArray).
bool ChooseScalars(vtkUnstructuredGrid* u, const Options& opt, const std::string& file,
  std::string scalars)
{
  vtkPointData* pd = u->GetPointData();
  if (!opt.array.empty())
  {
    if (!pd->GetArray(opt.array.c_str()))
    {
      std::cerr << "zsweep: " << file << " has no point array '" << opt.array
                << "' (--array); its point arrays: " << ListPointArrays(u) << "\n";
      return false;
    }
    scalars = opt.array;
  }
  if (scalars.empty() && !pd->GetScalars())
  {
    scalars = Name(FindColorArray(u));
  }
  if (!scalars.empty())
  {
    pd->SetActiveScalars(scalars.c_str());
  }
  return true;
}

// The number after "name:" in a synthetic grid's spec ("wavelet:5000000"), else 0.
long long SpecCount(const std::string& spec, const std::string& name)
{
  if (spec.compare(0, name.size() + 1, name + ":") != 0)
  {
    return 0;
  }
  return std::atoll(spec.c_str() + name.size() + 1);
}

// The wavelet on 2a cells a side with a chosen so that cellsPerVoxel (2a)^3 is nearest n.
vtkSmartPointer<vtkImageData> WaveletFor(long long n, int cellsPerVoxel)
{
  const int a = std::max(1, static_cast<int>(std::lround(0.5 * std::cbrt(double(n) / cellsPerVoxel))));
  vtkNew<vtkRTAnalyticSource> wavelet;
  wavelet->SetWholeExtent(-a, a, -a, a, -a, a);
  wavelet->Update();
  return wavelet->GetOutput();
}

// The wavelet's voxels as hexahedra of a warped grid: every point moved by a quarter of a
// cell along sin waves 16 cells long across the other two axes, so the cells are not
// parallelepipeds and their field is trilinear in a curved cell (the native path's case).
vtkSmartPointer<vtkUnstructuredGrid> WarpedHexahedra(vtkImageData* image)
{
  int dims[3];
  image->GetDimensions(dims);
  const double h = image->GetSpacing()[0], k = 2.0 * vtkMath::Pi() / (16.0 * h), amp = 0.25 * h;
  vtkNew<vtkPoints> points;
  points->SetDataTypeToFloat();
  points->SetNumberOfPoints(image->GetNumberOfPoints());
  for (vtkIdType i = 0; i < image->GetNumberOfPoints(); ++i)
  {
    double p[3];
    image->GetPoint(i, p);
    points->SetPoint(i, p[0] + amp * std::sin(k * (p[1] + p[2])),
      p[1] + amp * std::sin(k * (p[2] - p[0])), p[2] + amp * std::sin(k * (p[0] + 0.5 * p[1])));
  }
  const vtkIdType cells = static_cast<vtkIdType>(dims[0] - 1) * (dims[1] - 1) * (dims[2] - 1);
  vtkNew<vtkIdTypeArray> offsets, connectivity;
  offsets->SetNumberOfValues(cells + 1);
  connectivity->SetNumberOfValues(8 * cells);
  vtkIdType c = 0;
  auto id = [&](int i, int j, int l) { return (static_cast<vtkIdType>(l) * dims[1] + j) * dims[0] + i; };
  for (int l = 0; l + 1 < dims[2]; ++l)
  {
    for (int j = 0; j + 1 < dims[1]; ++j)
    {
      for (int i = 0; i + 1 < dims[0]; ++i, ++c)
      {
        const vtkIdType v[8] = { id(i, j, l), id(i + 1, j, l), id(i + 1, j + 1, l),
          id(i, j + 1, l), id(i, j, l + 1), id(i + 1, j, l + 1), id(i + 1, j + 1, l + 1),
          id(i, j + 1, l + 1) };
        offsets->SetValue(c, 8 * c);
        for (int m = 0; m < 8; ++m)
        {
          connectivity->SetValue(8 * c + m, v[m]);
        }
      }
    }
  }
  offsets->SetValue(cells, 8 * cells);
  vtkNew<vtkCellArray> cellArray;
  cellArray->SetData(offsets, connectivity);
  auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
  grid->SetPoints(points);
  grid->SetCells(VTK_HEXAHEDRON, cellArray);
  grid->GetPointData()->SetScalars(image->GetPointData()->GetScalars());
  return grid;
}

Grid Load(const std::string& file, const Options& opt)
{
  Grid g;
  vtkSmartPointer<vtkDataObject> data;
  std::string scalars;
  if (const long long n = SpecCount(file, "hex-wavelet"))
  {
    // Native hexahedra only (no tetrahedra: the scale rows at millions of cells).
    g.native = WarpedHexahedra(WaveletFor(n, 1));
    g.name = "hex-wavelet-" + std::to_string(g.native->GetNumberOfCells());
    return ChooseScalars(g.native, opt, file, "RTData") ? g : Grid();
  }
  if (const long long n = SpecCount(file, "wavelet"))
  {
    data = WaveletFor(n, 5); // 5 tetrahedra a voxel
    scalars = "RTData";
    g.name = "wavelet-" + std::to_string(5LL * vtkImageData::SafeDownCast(data)->GetNumberOfCells());
  }
  else if (file == "wavelet")
  {
    vtkNew<vtkRTAnalyticSource> wavelet;
    wavelet->SetWholeExtent(-20, 20, -20, 20, -20, 20);
    wavelet->Update();
    data = wavelet->GetOutput();
    scalars = "RTData";
    g.name = "wavelet";
  }
  else if (file.size() > 7 && file.compare(file.size() - 7, 7, "xyz.bin") == 0)
  {
    vtkNew<vtkMultiBlockPLOT3DReader> reader;
    reader->SetXYZFileName(file.c_str());
    reader->SetQFileName((file.substr(0, file.size() - 7) + "q.bin").c_str());
    reader->SetScalarFunctionNumber(100);
    reader->Update();
    data = reader->GetOutput()->GetBlock(0);
    scalars = "Density";
    g.name = BaseName(file.substr(0, file.size() - 7));
  }
  else if (file.find(".ex2") != std::string::npos || file.find(".exo") != std::string::npos)
  {
    vtkNew<vtkExodusIIReader> reader;
    reader->SetFileName(file.c_str());
    reader->UpdateInformation();
    reader->SetAllArrayStatus(vtkExodusIIReader::NODAL, 1);
    reader->Update();
    data = reader->GetOutput();
    scalars = "Temp";
    g.name = BaseName(file);
  }
  else
  {
    data = ReadAny(file);
    g.name = BaseName(file);
  }
  if (!data)
  {
    return g;
  }
  g.tetra = ToUnstructured(data, true);
  auto native = ToUnstructured(data, false);
  bool allTetra = true;
  for (vtkIdType c = 0; c < native->GetNumberOfCells() && allTetra; ++c)
  {
    allTetra = native->GetCellType(c) == VTK_TETRA;
  }
  if (!allTetra)
  {
    g.native = native;
  }
  for (vtkUnstructuredGrid* u : { g.tetra.Get(), g.native.Get() })
  {
    if (u && !ChooseScalars(u, opt, file, scalars))
    {
      return Grid();
    }
  }
  return g;
}

// Blue - green - red over the scalar range, opacity rising to 0.3 per `unit`.
vtkSmartPointer<vtkVolumeProperty> MakeProperty(const double range[2], double unit)
{
  auto property = vtkSmartPointer<vtkVolumeProperty>::New();
  vtkNew<vtkColorTransferFunction> color;
  color->AddRGBPoint(range[0], 0.2, 0.2, 1.0);
  color->AddRGBPoint(0.5 * (range[0] + range[1]), 0.2, 1.0, 0.2);
  color->AddRGBPoint(range[1], 1.0, 0.2, 0.2);
  vtkNew<vtkPiecewiseFunction> opacity;
  opacity->AddPoint(range[0], 0.02);
  opacity->AddPoint(range[1], 0.3);
  property->SetColor(color);
  property->SetScalarOpacity(opacity);
  property->SetScalarOpacityUnitDistance(unit);
  return property;
}

// The reference's transfer function: the property's colour and opacity at the union of
// their nodes (both are linear between these in the bench's property).
raymappers::test::RefTransferFunction ReferenceTransferFunction(vtkVolumeProperty* property)
{
  raymappers::test::RefTransferFunction tf;
  vtkColorTransferFunction* color = property->GetRGBTransferFunction(0);
  vtkPiecewiseFunction* opacity = property->GetScalarOpacity(0);
  double node[6];
  std::vector<double> xs;
  for (int i = 0; i < color->GetSize(); ++i)
  {
    color->GetNodeValue(i, node);
    xs.push_back(node[0]);
  }
  for (int i = 0; i < opacity->GetSize(); ++i)
  {
    opacity->GetNodeValue(i, node);
    xs.push_back(node[0]);
  }
  std::sort(xs.begin(), xs.end());
  xs.erase(std::unique(xs.begin(), xs.end()), xs.end());
  for (const double x : xs)
  {
    double rgb[3];
    color->GetColor(x, rgb);
    tf.s.push_back(x);
    tf.rgb.insert(tf.rgb.end(), rgb, rgb + 3);
    tf.alpha.push_back(opacity->GetValue(x));
  }
  tf.unitDistance = property->GetScalarOpacityUnitDistance(0);
  return tf;
}

// An image (RGB, 0..255, over white) of trace(o, d) -> premultiplied RGBA for the camera
// `view` sets around `grid`, with rays from VTK's composite projection matrix.
template<typename TraceFn>
vtkSmartPointer<vtkImageData> TraceImage(const Options& opt,
  vtkUnstructuredGrid* grid,
  const std::function<void(vtkCamera*)>& view,
  TraceFn trace)
{
  // The camera, as the harness sets it up (view, then the clipping range from the data).
  vtkNew<vtkRenderer> ren;
  vtkNew<vtkVolume> volume;
  vtkNew<vtkUnstructuredGridVolumeRayCastMapper> boundsOnly;
  boundsOnly->SetInputData(grid);
  volume->SetMapper(boundsOnly);
  ren->AddVolume(volume);
  view(ren->GetActiveCamera());
  ren->ResetCameraClippingRange();
  const double aspect = double(opt.width) / opt.height;
  vtkNew<vtkMatrix4x4> inverse;
  inverse->DeepCopy(ren->GetActiveCamera()->GetCompositeProjectionTransformMatrix(aspect, -1, 1));
  inverse->Invert();

  auto image = vtkSmartPointer<vtkImageData>::New();
  image->SetDimensions(opt.width, opt.height, 1);
  image->AllocateScalars(VTK_UNSIGNED_CHAR, 3);
  auto* out = static_cast<unsigned char*>(image->GetScalarPointer());
  tbb::parallel_for(0, opt.height, [&](int j) {
    std::vector<std::size_t> candidates;
    for (int i = 0; i < opt.width; ++i)
    {
      const double x = 2.0 * (i + 0.5) / opt.width - 1.0, y = 2.0 * (j + 0.5) / opt.height - 1.0;
      double nearP[4] = { x, y, -1, 1 }, farP[4] = { x, y, 1, 1 }, a[4], b[4];
      inverse->MultiplyPoint(nearP, a);
      inverse->MultiplyPoint(farP, b);
      const raymappers::Vec3d o(a[0] / a[3], a[1] / a[3], a[2] / a[3]);
      const raymappers::Vec3d e(b[0] / b[3], b[1] / b[3], b[2] / b[3]);
      const std::array<double, 4> rgba = trace(o, raymappers::normalize(e - o), candidates);
      unsigned char* px = out + 3 * (static_cast<std::size_t>(j) * opt.width + i);
      for (int c = 0; c < 3; ++c)
      {
        const double v = rgba[static_cast<std::size_t>(c)] + (1.0 - rgba[3]); // over white
        px[c] = static_cast<unsigned char>(std::lround(std::clamp(v, 0.0, 1.0) * 255.0));
      }
    }
  });
  return image;
}

// The corners (cell.p) and point scalars (cell.s) of the grid's cell c, in its point order.
template<typename RefCell>
void ReadCorners(vtkUnstructuredGrid* grid, vtkIdType c, vtkIdList* ids, RefCell& cell)
{
  vtkDataArray* s = grid->GetPointData()->GetScalars();
  grid->GetCellPoints(c, ids);
  for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k)
  {
    double p[3];
    grid->GetPoint(ids->GetId(k), p);
    cell.p[static_cast<std::size_t>(k)] = raymappers::Vec3d(p[0], p[1], p[2]);
    cell.s[static_cast<std::size_t>(k)] = s->GetComponent(ids->GetId(k), 0);
  }
}

// The brute-force reference image of the tetrahedra (UnstructuredReference.h).
vtkSmartPointer<vtkImageData> ReferenceImage(const Options& opt,
  vtkUnstructuredGrid* tetra,
  vtkVolumeProperty* property,
  const std::function<void(vtkCamera*)>& view,
  double& ms)
{
  const double t0 = Now();
  std::vector<raymappers::test::RefTetra> tets(static_cast<std::size_t>(tetra->GetNumberOfCells()));
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < tetra->GetNumberOfCells(); ++c)
  {
    ReadCorners(tetra, c, ids, tets[static_cast<std::size_t>(c)]);
  }
  const raymappers::test::ReferenceTetraGrid grid(tets);
  const raymappers::test::RefTransferFunction tf = ReferenceTransferFunction(property);
  auto image = TraceImage(opt, tetra, view,
    [&](const raymappers::Vec3d& o, const raymappers::Vec3d& d, std::vector<std::size_t>& candidates) {
      grid.candidates(o, d, 0.0, candidates);
      return raymappers::test::traceReference(tets, false, tf, o, d, 0.0, &candidates, 32);
    });
  ms = Now() - t0;
  return image;
}

// The converged reference of the hexahedra's, wedges' and pyramids' own fields inside their
// bilinear faces (TrilinearReference.h), integrated with steps of at most `step` (null when
// some cell is of another type); `failures` counts the points whose map was not inverted.
vtkSmartPointer<vtkImageData> TrilinearReferenceImage(const Options& opt,
  vtkUnstructuredGrid* native,
  vtkVolumeProperty* property,
  const std::function<void(vtkCamera*)>& view,
  double step,
  double& ms,
  long& failures)
{
  const double t0 = Now();
  std::vector<raymappers::test::RefCurvedCell> cells;
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < native->GetNumberOfCells(); ++c)
  {
    raymappers::test::RefCurvedCell h;
    switch (native->GetCellType(c))
    {
      case VTK_HEXAHEDRON:
        break;
      case VTK_WEDGE:
        h.shape = raymappers::test::RefShape::Wedge;
        break;
      case VTK_PYRAMID:
        h.shape = raymappers::test::RefShape::Pyramid;
        break;
      default:
        return nullptr;
    }
    ReadCorners(native, c, ids, h);
    cells.push_back(h);
  }
  const raymappers::test::ReferenceTetraGrid grid(cells);
  const raymappers::test::RefTransferFunction tf = ReferenceTransferFunction(property);
  std::atomic<long> failed{ 0 };
  auto image = TraceImage(opt, native, view,
    [&](const raymappers::Vec3d& o, const raymappers::Vec3d& d, std::vector<std::size_t>& candidates) {
      grid.candidates(o, d, 0.0, candidates);
      raymappers::test::TrilinearTraceCounts counts;
      const auto rgba = raymappers::test::traceTrilinearReference(cells, tf, o, d, 0.0, step, &counts, &candidates);
      failed += counts.failures;
      return rgba;
    });
  failures = failed;
  ms = Now() - t0;
  return image;
}
// Whether --only selects some native row (the trilinear reference is made only for them).
bool NativeRowSelected(const Options& opt)
{
  return opt.only.empty() ||
    std::any_of(opt.only.begin(), opt.only.end(),
      [](const std::string& o) { return o.find("native") != std::string::npos; });
}
} // namespace

std::vector<Row> RunZSweep(const Options& opt)
{
  std::vector<Row> rows;
  std::vector<std::string> files = opt.data;
  if (files.empty())
  {
    const std::string dataDir = std::string(RAYMAPPERS_SOURCE_DIR) + "/Data/";
    files = { dataDir + "bluntfinxyz.bin", dataDir + "combxyz.bin", dataDir + "disk_out_ref.ex2",
      "wavelet" };
  }
  WarmUp(opt);
  for (const std::string& file : files)
  {
    const Grid g = Load(file, opt);
    vtkUnstructuredGrid* shown = g.tetra ? g.tetra : g.native; // the views' and colours' grid
    if (!shown || shown->GetNumberOfCells() == 0 || !shown->GetPointData()->GetScalars())
    {
      std::cerr << "zsweep: cannot read a grid with scalars from " << file << "\n";
      continue;
    }
    double range[2], b[6];
    shown->GetPointData()->GetScalars()->GetRange(range);
    shown->GetBounds(b);
    const double diag = std::sqrt((b[1] - b[0]) * (b[1] - b[0]) + (b[3] - b[2]) * (b[3] - b[2]) +
      (b[5] - b[4]) * (b[5] - b[4]));
    auto property = MakeProperty(range, 0.05 * diag);
    const long long cells = g.tetra ? g.tetra->GetNumberOfCells() : 0;
    std::cout << g.name << ": " << cells << " tetrahedra"
              << (g.native ? ", " + std::to_string(g.native->GetNumberOfCells()) + " native cells"
                           : std::string())
              << ", scalars '" << Name(shown->GetPointData()->GetScalars()) << "'\n";

    for (const std::string view : { "far", "side", "close" })
    {
      if (!ViewSelected(opt, view))
      {
        continue;
      }
      auto camera = [&](vtkCamera* cam) {
        const double c[3] = { 0.5 * (b[0] + b[1]), 0.5 * (b[2] + b[3]), 0.5 * (b[4] + b[5]) };
        cam->SetFocalPoint(c);
        cam->SetViewUp(0, 1, 0);
        cam->SetViewAngle(30);
        if (view == "side")
        {
          cam->SetPosition(c[0] + 2.0 * diag, c[1] + 0.3 * diag, c[2] + 0.2 * diag);
        }
        else
        {
          cam->SetPosition(c[0] + 0.9 * diag, c[1] + 0.6 * diag, c[2] + 1.6 * diag);
        }
        if (view == "close")
        {
          cam->Zoom(2.5);
        }
      };
      const std::string dataset = g.name + "-" + view;

      // The reference image (the error columns need it), unless --no-reference or the grid
      // has no tetrahedra (a native grid generated for the scale rows).
      double referenceMs = 0;
      const vtkSmartPointer<vtkImageData> reference = opt.references && g.tetra
        ? ReferenceImage(opt, g.tetra, property, camera, referenceMs)
        : nullptr;
      if (reference)
      {
        Result r;
        r.row = Row{ "zsweep", dataset, "reference", "brute-force;double;simpson-32",
          opt.width, opt.height, cells, 0, referenceMs, -1, -1, 0 };
        r.image = reference;
        Record(opt, r, rows);
      }
      // The native rows' reference: the hexahedra's trilinear field in their bilinear faces,
      // at steps of diag / 2000, and once at twice that step to show it has converged (that
      // row's error columns are its difference from the finer one).
      vtkSmartPointer<vtkImageData> trilinear;
      if (opt.references && g.native && NativeRowSelected(opt))
      {
        for (const double step : { 1.0 / 1000, 1.0 / 2000 })
        {
          long failures = 0;
          Result r;
          auto image = TrilinearReferenceImage(opt, g.native, property, camera, step * diag,
            r.row.renderMs, failures);
          if (!image)
          {
            break;
          }
          r.row = Row{ "zsweep", dataset, "reference",
            "trilinear;rk4;step=diag/" + std::to_string(std::lround(1 / step)), opt.width,
            opt.height, g.native->GetNumberOfCells(), 0, r.row.renderMs, -1, -1, 0 };
          r.image = image;
          if (trilinear)
          {
            Compare(trilinear, image, r.row.rmse, r.row.maxErr);
          }
          if (failures)
          {
            std::cout << "  trilinear reference: " << failures << " points not inverted\n";
          }
          Record(opt, r, rows);
          trilinear = image;
        }
      }

      vtkSmartPointer<vtkZSweepVolumeMapper> ours;
      auto zsweep = [&](vtkUnstructuredGrid* grid, int integrator, int tile, int K, int p = 1,
                      bool sparse = false, int cellField = VTK_ZSWEEP_CELL_FIELD_NATIVE) {
        return [&, grid, integrator, tile, K, p, sparse, cellField](vtkRenderer* ren) {
          ours = vtkSmartPointer<vtkZSweepVolumeMapper>::New();
          ours->SetInputData(grid);
          ours->SetSparsification(sparse);
          ours->SetCellField(cellField);
          ours->SetIntegrator(integrator);
          ours->SetTileSize(tile);
          ours->SetListThreshold(K);
          ours->SetSubsampling(p);
          vtkNew<vtkVolume> volume;
          volume->SetMapper(ours);
          volume->SetProperty(property);
          ren->AddVolume(volume);
        };
      };
      auto detail = [&]() {
        vtkRayMapperStatistics* st = ours->GetStatistics();
        std::ostringstream s;
        s << "mesh " << st->GetPhaseTime("mesh") << " ms (" << st->GetCounter("mesh_bytes") / 1048576.0
          << " MB, " << st->GetCounter("kept_cells") << " cells kept), decode "
          << st->GetPhaseTime("decode") << " ms, project " << st->GetPhaseTime("project") << " ms, bin " << st->GetPhaseTime("bin")
          << " ms, order " << st->GetPhaseTime("order") << " ms (" << st->GetCounter("order_moves")
          << " moves, " << st->GetCounter("order_sorts") << " full sorts), sweep " << st->GetPhaseTime("sweep") << " ms; entries " << st->GetCounter("entries")
          << ", segments " << st->GetCounter("segments") << ", max list "
          << st->GetCounter("max_list") << ", K growths " << st->GetCounter("k_growths")
          << ", flushes " << st->GetCounter("flushes") << ", transparent segments "
          << st->GetCounter("transparent_segments") << ", curved segments "
          << st->GetCounter("curved_segments") << " (" << st->GetCounter("curved_pieces")
          << " pieces)";
        return s.str();
      };
      auto vtkMapper = [&](vtkUnstructuredGridVolumeMapper* mapper) {
        return [&, mapper](vtkRenderer* ren) {
          mapper->SetInputData(g.tetra);
          vtkNew<vtkVolume> volume;
          volume->SetMapper(mapper);
          volume->SetProperty(property);
          ren->AddVolume(volume);
        };
      };

      // The mesh build of a time step (the grid marked modified): build_ms is its median.
      auto meshMs = [&]() { return ours->GetStatistics()->GetPhaseTime("mesh"); };
      auto touch = [&]() { ours->GetInput()->Modified(); };
      std::vector<Method> methods;
      methods.push_back({ "zsweep", "exact", zsweep(g.tetra, VTK_ZSWEEP_INTEGRATOR_EXACT, 32, 16),
        meshMs, touch, detail });
      // Sparsification (section 4.3.5): the same image, the mesh stored through the kept cells.
      methods.push_back({ "zsweep", "exact;sparse",
        zsweep(g.tetra, VTK_ZSWEEP_INTEGRATOR_EXACT, 32, 16, 1, true), meshMs, touch, detail });
      if (g.native)
      {
        methods.push_back({ "zsweep", "native-cells;exact",
          zsweep(g.native, VTK_ZSWEEP_INTEGRATOR_EXACT, 32, 16), meshMs, touch, detail });
        methods.push_back({ "zsweep", "native-cells;sparse",
          zsweep(g.native, VTK_ZSWEEP_INTEGRATOR_EXACT, 32, 16, 1, true), meshMs, touch, detail });
        // The cells' own (trilinear) field above; here the split faces' linear field.
        methods.push_back({ "zsweep", "native-cells;split-faces",
          zsweep(g.native, VTK_ZSWEEP_INTEGRATOR_EXACT, 32, 16, 1, false,
            VTK_ZSWEEP_CELL_FIELD_SPLIT_FACES),
          meshMs, touch, detail });
      }
      methods.push_back({ "zsweep", "farias", zsweep(g.tetra, VTK_ZSWEEP_INTEGRATOR_FARIAS, 32, 16),
        nullptr, nullptr, detail });
      methods.push_back({ "zsweep", "midpoint",
        zsweep(g.tetra, VTK_ZSWEEP_INTEGRATOR_MIDPOINT, 32, 16), nullptr, nullptr, detail });
      if (view == "far")
      {
        for (const int tile : { 16, 64, 128 })
        {
          methods.push_back({ "zsweep", "tile=" + std::to_string(tile),
            zsweep(g.tetra, VTK_ZSWEEP_INTEGRATOR_EXACT, tile, 16), nullptr, nullptr, detail });
        }
        for (const int K : { 4, 64 })
        {
          methods.push_back({ "zsweep", "K=" + std::to_string(K),
            zsweep(g.tetra, VTK_ZSWEEP_INTEGRATOR_EXACT, 32, K), nullptr, nullptr, detail });
        }
      }
      // Time-critical rendering: p x p fewer rays (chapter 3), in every view, so that each
      // view's error against time can be set beside the approximate projected tetrahedra's.
      for (const int p : { 2, 3, 4, 6, 9 })
      {
        methods.push_back({ "zsweep", "p=" + std::to_string(p),
          zsweep(g.tetra, VTK_ZSWEEP_INTEGRATOR_EXACT, 32, 16, p), nullptr, nullptr, detail });
      }
      vtkNew<vtkUnstructuredGridVolumeZSweepMapper> vtkZSweep;
      vtkNew<vtkUnstructuredGridVolumeRayCastMapper> bunyk;
      vtkNew<vtkProjectedTetrahedraMapper> projected;
      methods.push_back({ "vtk-zsweep", "default", vtkMapper(vtkZSweep), nullptr, nullptr, nullptr });
      methods.back().repeat = 1;
      methods.push_back({ "vtk-bunyk", "default", vtkMapper(bunyk), nullptr, nullptr, nullptr });
      methods.push_back(
        { "vtk-projected-tetra", "default", vtkMapper(projected), nullptr, nullptr, nullptr });

      for (const Method& m : methods)
      {
        const bool native = m.setting.find("native") != std::string::npos;
        if (!Selected(opt, m) || (!native && !g.tetra))
        {
          continue;
        }
        Result r = Measure(opt, m, camera);
        r.row.suite = "zsweep";
        r.row.dataset = dataset;
        r.row.items = native ? g.native->GetNumberOfCells() : cells;
        // The native rows against the trilinear reference where there is one (all cells
        // hexahedra, wedges or pyramids), the others against the tetrahedra's.
        vtkImageData* against = native && trilinear ? trilinear.Get() : reference.Get();
        if (against)
        {
          Compare(r.image, against, r.row.rmse, r.row.maxErr);
        }
        Record(opt, r, rows);
      }
    }
  }
  return rows;
}

} // namespace bench
