// The fluid half of the sph suite: vtkSPHFluidMapper (the view-adaptive voxelization into
// compressed spans of Zirr and Dachsbacher 2015) and its filter vtkSPHVoxelizer, against
// what a ParaView user does today to see a fluid's surface: vtkSPHInterpolator onto an
// image grid, an isosurface by vtkContourFilter, ordinary rendering.
//
// Data (without --data): the coarse PySPH dam break Data/dam_break_coarse_00674.vtk (9,360
// particles, dx = 0.04 m), the fine frame the volume half picks (build/data/
// dam_break_fine_01188.vtk, 203,278 particles, dx = 0.0148 m, t = 0.2 s), and two derived
// sets:
//   <fine>-refined2  the fine frame with every particle replaced by a 2 x 2 x 2 lattice of
//                    particles at +-dx/4 on each axis, h halved, m / 8, rho and vmag kept
//                    (1,626,224 particles: the same fluid at half the spacing), for the
//                    stage table with more than a million particles; --data FILE+refined2
//                    makes it from another PySPH file;
//   layers24         the synthetic set of the paper's figure 8: 24 sheets of particles facing
//                    the camera, each a 100 x 100 square lattice of spacing 1 with radius
//                    0.75 (the spheres overlap: a sheet has no holes), 4 apart along the view
//                    axis (240,000 particles), seen from 250 in front of the first; --data
//                    layers24 selects it.
// Fluid radius on the dam break: r = 0.8 h = 1.04 dx (ScaleArray h, ScaleFactor 0.8;
// PySPH's h = 1.3 dx; as TestSPHFluidMapper), no gap bridging. Other data: --radius, else a
// radius array, else 0.8 times its h array (or --h), else the typical spacing (SetFluidRadius).
// A radius above sqrt(3)/2 dx = 0.87 dx covers a particle lattice's cells whole, so the union
// of spheres has no holes inside the fluid, and boundary-cell culling (FluidCells.h) can
// prove the inner cells full (its cover test needs a margin of about 0.1 r). The 0.5 level
// set of the volume fraction lies about dx/2 beyond the outermost centres, so the spheres'
// surface lies about 0.5 dx beyond the contour route's: the rows' depth_bias measures it,
// depth_mean_abs includes it.
//
// Methods (CSV method column; views "outside" and "surface" as the volume half):
//   sph-voxel              the water look: Translucency on, RefractiveIndex 1.33, Bounces 4,
//                          AbsorptionColor (4, 1.5, 0.8) per m, Density 1, Color (0.55, 0.75,
//                          0.95), Ambient 0.25, Diffuse 0.75, Specular 0.3, SpecularPower 40
//                          (as TestSPHFluidMapper), AngleResolution 14, MaximumLayers 16384,
//                          MaximumSpans 7, MemoryBudget 0 (automatic), SmoothingRadius dx,
//                          SmoothingIterations 20, no ambient occlusion
//   sph-voxel-translucent  the same with RefractiveIndex 1 (translucency only): the stage
//                          table's "render translucent"
//   sph-voxel-noculling    the water look with BoundaryCulling off: every particle splatted
//                          (same spans; what the culling saves in the splat and costs in
//                          build_ms)
//   sph-voxel-angle-A      A = 28, 14, 7 degrees, MaximumLayers 131072 (so that 7 degrees is
//                          reached in the close view up to about 1024 rows; angle_deg says
//                          what was), no smoothing (the paper's figure 6)
//   sph-voxel-spans-S      S = 1..7 spans kept (the front depth changes only through the
//                          smoothing, which keeps each depth between its column's
//                          neighbours; the refracted image through the march)
//   sph-voxel-smooth-N     SmoothingRadius dx with at most N = 0, 2, 5, 10, 20, 40, 80
//                          iterations (each point takes min(N, ceil(dx / pixel width))): the
//                          paper's distance-dependent filter, cut at N
//   sph-voxel-reference    the references: AngleResolution 2 degrees with MaximumLayers
//                          262144 (2 degrees reached in the close view up to 540 rows; at
//                          1024 rows about 2.6), MaximumSpans 16, MemoryBudget automatic; one
//                          without smoothing (for the angle sweep and the contour route) and
//                          one with SmoothingRadius dx and 1000 iterations (the filter's own
//                          limit, 255: converged) for the rows that smooth. Measured (one
//                          frame) when a method that is compared with it is selected
//   sph-contour-surface-gridN
//                          N = 64, 128, 256: the user's route. Resample (the volume half's
//                          vtkSPHInterpolator, Wendland C2 with PySPH's h, V = m / rho) onto a
//                          grid of N points along the longest axis, vtkContourFilter of its
//                          "Shepard Summation" sum_j V_j W_j (the volume fraction) at 0.5, as
//                          ParaView's Contour filter on image data (synchronized templates,
//                          normals on, scalars off), drawn by vtkPolyDataMapper opaque in the
//                          fluid's colour and material; frame_ms = resample + contour + the
//                          first frame
// On <fine>-refined2 only sph-voxel and sph-voxel-translucent run (the stage table); on
// layers24 only sph-voxel-spans-S and sph-voxel-angle-A (with one span), translucent
// (RefractiveIndex 1) with a black fluid and a grey absorption kappa = 0.04 per unit over a
// white background (Specular 0), so that a pixel shows exactly
// the transmittance T = exp(-kappa l) of its ray's total fluid length l: rmse and max_err
// compare the image with T computed exactly (l the union of the ray's chords through the
// spheres), thickness_rel_err the voxelizer's Thickness with l.
// Without --only the fluid half runs what is cheap: sph-voxel, sph-voxel-translucent and
// sph-voxel-noculling on every set (the stage table) and the layers24 rows. The sweeps, the references and the
// contour route (minutes a frame for the references at 1024 rows in the close view) run when
// --only selects them: --only sph-voxel selects every fluid row (and the references they
// need), --only sph-voxel: the water look alone, --only sph-contour-surface the user's route
// (--only sph-contour also selects the volume half's sph-contour effect).
//
// Measured per row (CSV columns after the volume half's; VoxelCsvColumns):
//   build_ms           the rebuild after a new time step (median over --repeat): the
//                      particles and the culling cells (phases particles + cells);
//                      render_ms the median frame; frame_ms = build_ms + render_ms
//   splat_ms ... draw_ms
//                      the mapper's phases (GetStatistics()), median over the frames after
//                      the first: splat, compress, connect (links and neighbourhoods), filter
//                      (smoothing), normals, ao, render (translucent: translucent_ms) or
//                      refract (refract_ms), draw
//   mem_mb             the voxelizer's peak temporary memory (counter peak_temporary_bytes:
//                      one tile's bit grid and the particles' footprints) / 2^20, which
//                      MemoryBudget bounds; contour rows: resident memory growth
//   layers, spans_found, spans_stored, tiles, filter_iterations
//                      counters of the last frame; angle_deg the angle resolution reached
//                      (vtkSPHVoxelizer's AngleResolutionReached)
//   depth_mean_abs, depth_rmse, depth_bias
//                      the front surface against the reference's: per pixel the depth zeta
//                      (distance from the eye plane along the view axis, world units) of the
//                      first entry, EntryDepth[0] of vtkSPHVoxelizer run with the renderer's
//                      camera and the row's settings (the mapper's voxelization exactly);
//                      for the contour route the window's depth buffer turned into zeta
//                      (ViewRays::zetaOfWindowDepth); mean |dz|, sqrt(mean dz^2) and mean dz
//                      (row minus reference) over the pixels where both have a surface
//   coverage_diff      the pixels where exactly one of the two has a surface over those
//                      where either has
//   normal_deg         mean angle between EntryNormal[0] and the reference's (voxel rows)
//   rmse, max_err      the image against the reference's image (same look: empty for
//                      sph-voxel-translucent and for the contour route, an opaque surface);
//                      on layers24 against the exact T
// At the end the stage table (the paper's table 2) of the sph-voxel and sph-voxel-translucent
// rows is printed.
#include "BenchRun.h"
#include "SPHSuite.h"
#include "Mappers/Common/ViewRays.h"
#include "vtkRayMapperRenderHelpers.h"
#include "vtkRayMapperStatistics.h"
#include "vtkSPHFluidMapper.h"
#include "vtkSPHVoxelizer.h"

#include "vtkActor.h"
#include "vtkCallbackCommand.h"
#include "vtkCamera.h"
#include "vtkCommand.h"
#include "vtkContourFilter.h"
#include "vtkDataArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkPolyDataMapper.h"
#include "vtkProperty.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <limits>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

namespace bench
{
namespace sph
{

const char* const VoxelCsvColumns =
  "contour_ms,splat_ms,compress_ms,connect_ms,filter_ms,normals_ms,ao_ms,translucent_ms,"
  "refract_ms,draw_ms,layers,angle_deg,spans_found,spans_stored,tiles,filter_iterations,"
  "depth_mean_abs,depth_rmse,depth_bias,coverage_diff,normal_deg,thickness_rel_err";

std::string EmptyVoxelCsv()
{
  const std::string columns = VoxelCsvColumns;
  return std::string(static_cast<std::size_t>(std::count(columns.begin(), columns.end(), ',')),
    ',');
}

namespace
{
constexpr double NaN = std::numeric_limits<double>::quiet_NaN();

// The settings of vtkSPHFluidMapper and vtkSPHVoxelizer that a row uses.
struct Fluid
{
  std::string radiusArray = "h"; // ScaleArray times radiusScale; empty: the constant radius
  double radiusScale = 0.8;
  bool culling = true;
  double radius = 1.0;
  double angle = 14;
  int layers = 16384;
  int spans = 7;
  double budget = 0; // MB; 0: the mappers' automatic budget
  double gap = 0;
  double smoothRadius = 0;
  int smoothIterations = 20;
  double ior = 1.33;
  std::array<double, 3> color{ 0.55, 0.75, 0.95 };
  std::array<double, 3> absorption{ 4.0, 1.5, 0.8 };
  double density = 1;
  double ambient = 0.25, diffuse = 0.75, specular = 0.3, specularPower = 40;

  // The CSV's setting: what differs between rows (no commas).
  std::string Describe() const
  {
    std::ostringstream s;
    s << "angle=" << angle << ";layers=" << layers << ";spans=" << spans;
    if (smoothRadius > 0)
    {
      s << ";smooth=" << smoothRadius << "x" << smoothIterations;
    }
    s << ";ior=" << ior;
    if (!culling)
    {
      s << ";culling=off";
    }
    if (budget != 0)
    {
      s << ";budget=" << budget;
    }
    return s.str();
  }

  template <typename T>
  void Apply(T* m) const
  {
    m->SetScaleArray(radiusArray.empty() ? nullptr : radiusArray.c_str());
    m->SetScaleFactor(radiusArray.empty() ? 1.0 : radiusScale);
    m->SetRadius(radius);
    m->SetAngleResolution(angle);
    m->SetMaximumLayers(layers);
    m->SetMaximumSpans(spans);
    m->SetMemoryBudget(budget);
    m->SetGapThreshold(gap);
    m->SetBoundaryCulling(culling);
    m->SetSmoothingRadius(smoothRadius);
    m->SetSmoothingIterations(smoothIterations);
  }
};

// The front surface of a view: per pixel (row 0 at the bottom) the depth zeta of the first
// entry and its normal (NaN where there is none), and the fluid's thickness along the ray.
struct Surface
{
  int width = 0, height = 0;
  std::vector<float> depth, normal, thickness;
  double angleReached = -1;
  std::array<double, 16> modelToClip{}; // the voxelizer's camera (row-major); 0: none
};

// vtkSPHVoxelizer with the renderer's camera and the row's settings: the voxelization the
// mapper rendered (TestSPHFluidMapper checks that they agree span for span).
Surface VoxelSurface(vtkPolyData* particles, const Fluid& f, vtkRenderer* ren, int w, int h)
{
  vtkNew<vtkSPHVoxelizer> voxelizer;
  voxelizer->SetInputData(particles);
  f.Apply(voxelizer.Get());
  voxelizer->SetCamera(ren->GetActiveCamera());
  voxelizer->ResetCameraOff();
  voxelizer->SetImageSize(w, h);
  voxelizer->Update();
  vtkImageData* out = voxelizer->GetOutput();
  vtkDataArray* entry = out->GetPointData()->GetArray("EntryDepth");
  vtkDataArray* normal = out->GetPointData()->GetArray("EntryNormal");
  vtkDataArray* thickness = out->GetPointData()->GetArray("Thickness");
  Surface s;
  s.width = w;
  s.height = h;
  const vtkIdType n = static_cast<vtkIdType>(w) * h;
  s.depth.resize(n);
  s.normal.resize(3 * n);
  s.thickness.resize(n);
  for (vtkIdType p = 0; p < n; ++p)
  {
    s.depth[p] = static_cast<float>(entry->GetComponent(p, 0));
    for (int c = 0; c < 3; ++c)
    {
      s.normal[3 * p + c] = static_cast<float>(normal->GetComponent(p, c));
    }
    s.thickness[p] = static_cast<float>(thickness->GetComponent(p, 0));
  }
  if (vtkDataArray* a = out->GetFieldData()->GetArray("AngleResolutionReached"))
  {
    s.angleReached = a->GetComponent(0, 0);
  }
  if (vtkDataArray* m = out->GetFieldData()->GetArray("ModelToClip"))
  {
    for (int k = 0; k < 16 && k < m->GetNumberOfTuples(); ++k)
    {
      s.modelToClip[k] = m->GetComponent(k, 0);
    }
  }
  return s;
}

// The front surface of what the window shows, from its depth buffer: zeta on each pixel's
// ray where the window depth is below 1 (the far plane: nothing drawn). No normals.
Surface WindowSurface(vtkRenderer* ren, vtkProp3D* prop)
{
  Surface s;
  const auto model = vtkRayMapperRenderHelpers::GatherModelTransform(prop);
  const std::array<double, 16> modelToClip =
    vtkRayMapperRenderHelpers::GatherModelToClip(ren, model, s.width, s.height);
  raymappers::ViewRays rays;
  const std::size_t n = static_cast<std::size_t>(s.width) * s.height;
  s.depth.assign(n, static_cast<float>(NaN));
  s.normal.assign(3 * n, static_cast<float>(NaN));
  s.thickness.assign(n, 0.f);
  std::vector<float> z(n);
  if (!rays.assign(modelToClip, s.width, s.height, raymappers::Vec3d(0, 0, 0)) ||
    !ren->GetRenderWindow()->GetZbufferData(0, 0, s.width - 1, s.height - 1, z.data()))
  {
    std::cerr << "sph: the window's depth could not be read\n";
    return s;
  }
  for (int j = 0; j < s.height; ++j)
  {
    for (int i = 0; i < s.width; ++i)
    {
      const std::size_t p = static_cast<std::size_t>(j) * s.width + i;
      if (z[p] < 1.f)
      {
        s.depth[p] = static_cast<float>(rays.zetaOfWindowDepth(i + 0.5, j + 0.5, z[p]));
      }
    }
  }
  return s;
}

struct SurfaceError
{
  double meanAbs = -1, rmse = -1, bias = NaN, coverage = -1, normalDeg = -1;
};

// A surface against the reference's (same view and size).
SurfaceError CompareSurfaces(const Surface& a, const Surface& ref)
{
  SurfaceError e;
  if (a.depth.size() != ref.depth.size() || a.depth.empty())
  {
    return e;
  }
  double sumAbs = 0, sumSq = 0, sum = 0, sumAngle = 0;
  long long both = 0, either = 0, one = 0, normals = 0;
  for (std::size_t p = 0; p < a.depth.size(); ++p)
  {
    const bool ha = std::isfinite(a.depth[p]), hr = std::isfinite(ref.depth[p]);
    either += ha || hr;
    one += ha != hr;
    if (!(ha && hr))
    {
      continue;
    }
    const double d = static_cast<double>(a.depth[p]) - ref.depth[p];
    ++both;
    sumAbs += std::fabs(d);
    sumSq += d * d;
    sum += d;
    const float* na = &a.normal[3 * p];
    const float* nr = &ref.normal[3 * p];
    if (std::isfinite(na[0]) && std::isfinite(nr[0]))
    {
      const double c = std::clamp(
        static_cast<double>(na[0]) * nr[0] + static_cast<double>(na[1]) * nr[1] +
          static_cast<double>(na[2]) * nr[2],
        -1.0, 1.0);
      sumAngle += std::acos(c) * 180.0 / 3.14159265358979323846;
      ++normals;
    }
  }
  if (both > 0)
  {
    e.meanAbs = sumAbs / both;
    e.rmse = std::sqrt(sumSq / both);
    e.bias = sum / both;
  }
  e.coverage = either > 0 ? static_cast<double>(one) / either : 0.0;
  if (normals > 0)
  {
    e.normalDeg = sumAngle / normals;
  }
  return e;
}

// The phases of every frame of a fluid mapper (a window observer).
struct FluidLog
{
  static constexpr const char* Phases[] = { "splat", "compress", "connect", "filter", "normals",
    "ao", "render", "refract", "draw" };
  static constexpr int N = sizeof(Phases) / sizeof(Phases[0]);
  std::array<std::vector<double>, N> ms;
  std::vector<double> frameMs;
  double t0 = 0;
  vtkSPHFluidMapper* mapper = nullptr;

  static void Start(vtkObject*, unsigned long, void* self, void*)
  {
    static_cast<FluidLog*>(self)->t0 = Now();
  }
  static void End(vtkObject*, unsigned long, void* self, void*)
  {
    auto* log = static_cast<FluidLog*>(self);
    log->frameMs.push_back(Now() - log->t0);
    if (log->mapper)
    {
      vtkRayMapperStatistics* st = log->mapper->GetStatistics();
      for (int k = 0; k < N; ++k)
      {
        log->ms[k].push_back(st->GetPhaseTime(Phases[k]));
      }
    }
  }
  void Attach(vtkRenderer* ren)
  {
    vtkNew<vtkCallbackCommand> start, end;
    start->SetCallback(&FluidLog::Start);
    start->SetClientData(this);
    end->SetCallback(&FluidLog::End);
    end->SetClientData(this);
    ren->GetRenderWindow()->AddObserver(vtkCommand::StartEvent, start);
    ren->GetRenderWindow()->AddObserver(vtkCommand::EndEvent, end);
  }
  // The median of phase k over the frames after the first (that one builds the particles).
  double Later(int k) const
  {
    const std::vector<double>& v = ms[k];
    return v.size() > 1 ? Median(std::vector<double>(v.begin() + 1, v.end()))
                        : (v.empty() ? -1.0 : v[0]);
  }
};

// What one voxel row measured beyond the common columns.
struct VoxelExtra
{
  double contourMs = -1;
  std::array<double, FluidLog::N> phaseMs;
  long long layers = -1, spansFound = -1, spansStored = -1, tiles = -1, filterIterations = -1;
  double angleDeg = -1;
  SurfaceError error;
  double thicknessRelErr = -1;
  VoxelExtra() { phaseMs.fill(-1); }

  std::string Csv() const
  {
    std::ostringstream s;
    s << Number(contourMs);
    for (double v : phaseMs)
    {
      s << "," << Number(v);
    }
    s << "," << Count(layers) << "," << Number(angleDeg) << "," << Count(spansFound) << ","
      << Count(spansStored) << "," << Count(tiles) << "," << Count(filterIterations) << ","
      << Number(error.meanAbs) << "," << Number(error.rmse) << ","
      << (std::isfinite(error.bias) ? std::to_string(error.bias) : std::string()) << ","
      << Number(error.coverage) << "," << Number(error.normalDeg) << ","
      << Number(thicknessRelErr);
    return s.str();
  }
};

// A dataset of the fluid half: particles, their spacing and the views to measure.
struct FluidData
{
  std::string name;
  vtkSmartPointer<vtkPolyData> particles;
  double dx = 0;        // particle spacing (PySPH: h / 1.3)
  bool stageOnly = false; // only the stage table's methods
  bool layers = false;  // the synthetic layers
  Dataset source;       // the PySPH frame (views, resample)
};

// The fine frame refined: each particle a 2 x 2 x 2 lattice at +-dx/4, h / 2, m / 8.
vtkSmartPointer<vtkPolyData> Refine(const Dataset& d, double dx)
{
  vtkPolyData* in = d.particles;
  const vtkIdType n = in->GetNumberOfPoints();
  vtkNew<vtkPoints> points;
  points->SetDataTypeToFloat();
  points->SetNumberOfPoints(8 * n);
  auto out = vtkSmartPointer<vtkPolyData>::New();
  out->SetPoints(points);
  vtkPointData* pin = in->GetPointData();
  struct Refined
  {
    vtkDataArray* source;
    vtkSmartPointer<vtkFloatArray> array;
    double factor; // h / 2, m / 8, the rest kept
  };
  std::vector<Refined> arrays;
  for (const auto& [name, factor] : { std::make_pair(d.smoothing.array, 0.5),
         std::make_pair(d.mass, 0.125), std::make_pair(d.density, 1.0),
         std::make_pair(d.value, 1.0) })
  {
    if (name.empty())
    {
      continue; // a constant h
    }
    auto a = vtkSmartPointer<vtkFloatArray>::New();
    a->SetName(name.c_str());
    a->SetNumberOfTuples(8 * n);
    out->GetPointData()->AddArray(a);
    arrays.push_back({ pin->GetArray(name.c_str()), a, factor });
  }
  const double q = 0.25 * dx;
  for (vtkIdType i = 0; i < n; ++i)
  {
    double p[3];
    in->GetPoint(i, p);
    for (int c = 0; c < 8; ++c)
    {
      const vtkIdType k = 8 * i + c;
      points->SetPoint(
        k, p[0] + (c & 1 ? q : -q), p[1] + (c & 2 ? q : -q), p[2] + (c & 4 ? q : -q));
      for (const Refined& a : arrays)
      {
        a.array->SetValue(k, static_cast<float>(a.factor * a.source->GetComponent(i, 0)));
      }
    }
  }
  return out;
}

// The synthetic layers (paper, figure 8): 24 sheets in the planes z = -4k, each a 100 x 100
// lattice of spacing 1 in x and y centred on the axis, radius 0.75.
constexpr int Sheets = 24, SheetSide = 100;
constexpr double SheetPitch = 4.0, LayerRadius = 0.75, LayerKappa = 0.04, LayerEye = 250.0;

vtkSmartPointer<vtkPolyData> MakeLayers()
{
  vtkNew<vtkPoints> points;
  points->SetDataTypeToFloat();
  for (int k = 0; k < Sheets; ++k)
  {
    for (int b = 0; b < SheetSide; ++b)
    {
      for (int a = 0; a < SheetSide; ++a)
      {
        points->InsertNextPoint(a - 0.5 * (SheetSide - 1), b - 0.5 * (SheetSide - 1), -SheetPitch * k);
      }
    }
  }
  auto out = vtkSmartPointer<vtkPolyData>::New();
  out->SetPoints(points);
  return out;
}

void LayersView(vtkCamera* cam)
{
  cam->SetFocalPoint(0, 0, -0.5 * SheetPitch * (Sheets - 1));
  cam->SetPosition(0, 0, LayerEye);
  cam->SetViewUp(0, 1, 0);
  cam->SetViewAngle(30);
}

// The exact fluid length along pixel (i, j)'s centre ray through the layers: the union of
// the chords of the spheres it meets, in world units. The ray is p(zeta) = A + zeta B
// (ViewRays); near sheet k only the lattice points within r + its lateral drift can be met.
double LayerLength(const raymappers::ViewRays& rays, int i, int j)
{
  const raymappers::Vec3d A = rays.start(i + 0.5, j + 0.5), B = rays.direction(i + 0.5, j + 0.5);
  const double bb = raymappers::dot(B, B);
  std::vector<std::pair<double, double>> chords;
  for (int k = 0; k < Sheets; ++k)
  {
    const double zk = -SheetPitch * k;
    if (B.z == 0)
    {
      continue;
    }
    const double zeta = (zk - A.z) / B.z;
    const double x = A.x + zeta * B.x, y = A.y + zeta * B.y;
    const double drift = LayerRadius * std::hypot(B.x, B.y) / std::fabs(B.z);
    const double reach = LayerRadius + drift;
    const double o = 0.5 * (SheetSide - 1);
    const int a0 = std::max(0, static_cast<int>(std::floor(x + o - reach)));
    const int a1 = std::min(SheetSide - 1, static_cast<int>(std::ceil(x + o + reach)));
    const int b0 = std::max(0, static_cast<int>(std::floor(y + o - reach)));
    const int b1 = std::min(SheetSide - 1, static_cast<int>(std::ceil(y + o + reach)));
    for (int b = b0; b <= b1; ++b)
    {
      for (int a = a0; a <= a1; ++a)
      {
        const raymappers::Vec3d c(a - o, b - o, zk);
        const raymappers::Vec3d ac = A - c;
        const double half = raymappers::dot(ac, B) / bb;
        const double disc = half * half - (raymappers::dot(ac, ac) - LayerRadius * LayerRadius) / bb;
        if (disc > 0)
        {
          chords.emplace_back(-half - std::sqrt(disc), -half + std::sqrt(disc));
        }
      }
    }
  }
  std::sort(chords.begin(), chords.end());
  double length = 0, lo = -1e300, hi = -1e300;
  for (const auto& [s, e] : chords)
  {
    if (s > hi)
    {
      length += hi - lo;
      lo = s;
      hi = e;
    }
    else
    {
      hi = std::max(hi, e);
    }
  }
  length += hi - lo;
  return length * std::sqrt(bb);
}

// The transmittance image's error: the window shows T = exp(-kappa l) (black fluid, grey
// absorption, white background); rmse and max over all pixels and channels, and the mean
// relative error of the voxelizer's thickness against l over the pixels with fluid.
// The rays are the voxelizer's (the renderer's camera, model = world coordinates).
void LayersError(vtkImageData* image, const Surface& s, Result& r, double& relErr)
{
  const int w = s.width, h = s.height;
  raymappers::ViewRays rays;
  int dims[3];
  image->GetDimensions(dims);
  if (!rays.assign(s.modelToClip, w, h, raymappers::Vec3d(0, 0, 0)) || dims[0] != w ||
    dims[1] != h)
  {
    std::cerr << "sph: layers24: no rays for the exact transmittance\n";
    return;
  }
  std::vector<double> length(static_cast<std::size_t>(w) * h);
  tbb::parallel_for(tbb::blocked_range<int>(0, h),
    [&](const tbb::blocked_range<int>& rows)
    {
      for (int j = rows.begin(); j != rows.end(); ++j)
      {
        for (int i = 0; i < w; ++i)
        {
          length[static_cast<std::size_t>(j) * w + i] = LayerLength(rays, i, j);
        }
      }
    });
  const auto* rgb = static_cast<const unsigned char*>(image->GetScalarPointer());
  double sumSq = 0, maxErr = 0, sumRel = 0;
  long long fluid = 0;
  for (std::size_t p = 0; p < length.size(); ++p)
  {
    const double T = std::exp(-LayerKappa * length[p]);
    for (int c = 0; c < 3; ++c)
    {
      const double d = rgb[3 * p + c] / 255.0 - T;
      sumSq += d * d;
      maxErr = std::max(maxErr, std::fabs(d));
    }
    if (length[p] > 0)
    {
      sumRel += std::fabs(s.thickness[p] - length[p]) / length[p];
      ++fluid;
    }
  }
  r.row.rmse = std::sqrt(sumSq / (3.0 * length.size()));
  r.row.maxErr = maxErr;
  relErr = fluid > 0 ? sumRel / fluid : -1;
}

// One measured voxel row: the method and what it leaves behind for the comparisons.
struct Row3
{
  Method method;
  std::function<void(vtkRenderer*)> inspect; // reads the surface after the final frame
  Fluid fluid;
  std::string reference; // "plain", "smooth" or "" (layers: analytic)
  std::shared_ptr<FluidLog> log;
  std::shared_ptr<vtkSmartPointer<vtkSPHFluidMapper>> mapper;
  std::shared_ptr<Surface> surface;
};

// Whether a fluid row runs: the --only selection, or without --only the cheap rows.
bool Wanted(const Options& opt, const Method& m, bool layers)
{
  if (!opt.only.empty())
  {
    return Selected(opt, m);
  }
  return layers || m.name == "sph-voxel" || m.name == "sph-voxel-translucent" ||
    m.name == "sph-voxel-noculling";
}

// The stage table's entries.
struct Stage
{
  std::string dataset;
  long long particles = 0, inView = 0;
  std::array<double, FluidLog::N> ms{};
  double translucentMs = -1, refractMs = -1, frameTranslucent = -1, frameRefract = -1;
  double memMb = 0;
  int width = 0, height = 0;
};

void PrintStageTable(const std::vector<Stage>& stages)
{
  if (stages.empty())
  {
    return;
  }
  std::printf("\nStages of vtkSPHFluidMapper (ms, median frame; cf. Zirr 2015, table 2; "
              "translucent and refract: the render phase (and the sum of the stages before "
              "it plus it); mem: peak temporary MB)\n");
  std::printf("%-48s %10s %10s %8s %8s %8s %8s %8s %16s %16s %7s\n", "dataset (view, size)",
    "particles", "in view", "splat", "compress", "connect", "filter", "normals",
    "translucent (S)", "refract (S)", "mem");
  for (const Stage& s : stages)
  {
    const double before = s.ms[0] + s.ms[1] + s.ms[2] + s.ms[3] + s.ms[4];
    char translucent[32] = "-", refract[32] = "-";
    if (s.translucentMs >= 0)
    {
      std::snprintf(translucent, sizeof translucent, "%.0f (%.0f)", s.translucentMs,
        before + s.translucentMs);
    }
    if (s.refractMs >= 0)
    {
      std::snprintf(refract, sizeof refract, "%.0f (%.0f)", s.refractMs, before + s.refractMs);
    }
    const std::string label =
      s.dataset + " " + std::to_string(s.width) + "x" + std::to_string(s.height);
    std::printf("%-48s %10lld %10lld %8.0f %8.0f %8.1f %8.0f %8.0f %16s %16s %7.0f\n",
      label.c_str(), s.particles, s.inView, s.ms[0], s.ms[1], s.ms[2], s.ms[3], s.ms[4],
      translucent, refract, s.memMb);
  }
  const auto most = std::max_element(stages.begin(), stages.end(),
    [](const Stage& a, const Stage& b) { return a.memMb < b.memMb; });
  std::printf("peak temporary memory: at most %.1f MB (%s), budget automatic\n", most->memMb,
    most->dataset.c_str());
}
} // namespace

namespace
{
// The particle spacing dx: PySPH's h / 1.3 when h is an array (PySPH writes h = 1.3 dx), else
// the typical spacing.
double FluidSpacing(const Dataset& d)
{
  if (!d.smoothing.array.empty())
  {
    return d.h / 1.3;
  }
  vtkRayMapperParticleSizes::SpacingCache cache;
  return vtkRayMapperParticleSizes::AutomaticLength(d.particles, 1.0, cache);
}

// The fluid radius: --radius; else a radius array (radius, radii, r, diameter x 0.5); else
// 0.8 h (the dam break's r = 0.8 h above) of the h array or of --h; else the automatic
// radius, 1 x the typical spacing (overlapping spheres without cavities).
void SetFluidRadius(const Dataset& d, const Options& opt, Fluid& f)
{
  const ParticleSize radius = ChooseSize(d.particles, vtkRayMapperParticleSizes::Role::Radius,
    false, FluidRadiusPerSpacing, opt.radius);
  f.radiusArray = radius.array;
  f.radiusScale = radius.scale;
  f.radius = radius.constant;
  std::string how = radius.how;
  const bool fromH =
    opt.radius <= 0 && radius.array.empty() && (!d.smoothing.array.empty() || opt.h > 0);
  if (fromH)
  {
    f.radiusArray = d.smoothing.array;
    f.radiusScale = 0.8 * d.smoothing.scale;
    f.radius = 0.8 * d.smoothing.constant;
    how = "0.8 x the smoothing length, " + d.smoothing.how;
  }
  std::cout << "sph: " << d.name << ": fluid radius " << how << "\n";
}
} // namespace

std::vector<Row> RunSPHVoxel(const Options& opt, const std::vector<std::string>& files)
{
  // The data: the files, and without --data the refined fine frame and the layers.
  std::vector<std::string> specs = files;
  if (opt.data.empty())
  {
    if (files.size() > 1)
    {
      specs.push_back(files.back() + "+refined2");
    }
    specs.push_back("layers24");
  }
  std::vector<Row> rows;
  std::vector<Stage> stages;
  for (const std::string& spec : specs)
  {
    FluidData fd;
    const std::string suffix = "+refined2";
    if (spec == "layers24")
    {
      fd.name = "layers24";
      fd.particles = MakeLayers();
      fd.dx = 1.0;
      fd.layers = true;
    }
    else
    {
      const bool refine =
        spec.size() > suffix.size() && spec.compare(spec.size() - suffix.size(), suffix.size(), suffix) == 0;
      fd.source = Load(refine ? spec.substr(0, spec.size() - suffix.size()) : spec, opt);
      if (!fd.source.particles || fd.source.particles->GetNumberOfPoints() == 0)
      {
        continue;
      }
      fd.dx = FluidSpacing(fd.source);
      fd.name = fd.source.name;
      fd.particles = fd.source.particles;
      if (refine)
      {
        fd.particles = Refine(fd.source, fd.dx);
        fd.dx *= 0.5;
        fd.name += "-refined2";
        fd.stageOnly = true;
      }
    }
    vtkPolyData* particles = fd.particles;
    const long long n = particles->GetNumberOfPoints();
    std::cout << fd.name << " (fluid): " << n << " particles, dx " << fd.dx << "\n";

    // The settings of the rows.
    Fluid water;
    if (!fd.layers)
    {
      SetFluidRadius(fd.source, opt, water);
    }
    water.smoothRadius = fd.dx;
    Fluid plain = water;
    plain.smoothRadius = 0;
    Fluid reference = plain;
    reference.angle = 2;
    reference.layers = 1 << 18;
    reference.spans = 16;
    Fluid smoothReference = reference;
    smoothReference.smoothRadius = fd.dx;
    smoothReference.smoothIterations = 1000;
    if (fd.layers)
    {
      water = Fluid();
      water.radiusArray.clear();
      water.radius = LayerRadius;
      water.ior = 1;
      water.color = { 0, 0, 0 };
      water.absorption = { 1, 1, 1 };
      water.density = LayerKappa;
      water.specular = 0;
    }

    std::map<int, std::shared_ptr<Resampled>> resampled; // the contour route's grids
    const std::vector<std::string> views =
      fd.layers ? std::vector<std::string>{ "front" } : std::vector<std::string>{ "outside", "surface" };
    for (const std::string& view : views)
    {
      if (!ViewSelected(opt, view))
      {
        continue;
      }
      const std::function<void(vtkCamera*)> camera =
        fd.layers ? std::function<void(vtkCamera*)>(LayersView) : View(fd.source, view);
      const std::string dataset = fd.name + "-" + view;

      auto fluidRow = [&](const std::string& name, const std::string& setting, const Fluid& f,
                        const std::string& ref)
      {
        Row3 o;
        o.fluid = f;
        o.reference = ref;
        o.log = std::make_shared<FluidLog>();
        o.mapper = std::make_shared<vtkSmartPointer<vtkSPHFluidMapper>>();
        o.surface = std::make_shared<Surface>();
        auto log = o.log;
        auto mapper = o.mapper;
        auto surface = o.surface;
        o.method.name = name;
        o.method.setting = setting.empty() ? f.Describe() : setting;
        o.method.setup = [particles, f, log, mapper](vtkRenderer* ren)
        {
          auto m = vtkSmartPointer<vtkSPHFluidMapper>::New();
          m->SetInputData(particles);
          f.Apply(m.Get());
          m->SetTranslucency(true);
          m->SetRefractiveIndex(f.ior);
          m->SetColor(f.color[0], f.color[1], f.color[2]);
          m->SetAbsorptionColor(f.absorption[0], f.absorption[1], f.absorption[2]);
          m->SetDensity(f.density);
          vtkNew<vtkVolumeProperty> property;
          property->SetAmbient(f.ambient);
          property->SetDiffuse(f.diffuse);
          property->SetSpecular(f.specular);
          property->SetSpecularPower(f.specularPower);
          vtkNew<vtkVolume> volume;
          volume->SetMapper(m);
          volume->SetProperty(property);
          ren->AddVolume(volume);
          *mapper = m;
          log->mapper = m;
          log->Attach(ren);
        };
        o.method.buildMs = [mapper]()
        {
          vtkRayMapperStatistics* st = (*mapper)->GetStatistics();
          return st->GetPhaseTime("particles") + st->GetPhaseTime("cells");
        };
        o.method.touch = [particles]() { particles->Modified(); };
        o.inspect = [particles, f, surface, &opt](vtkRenderer* ren)
        { *surface = VoxelSurface(particles, f, ren, opt.width, opt.height); };
        return o;
      };

      // The rows of this view.
      std::vector<Row3> measured;
      auto label = [](double v)
      {
        std::ostringstream s;
        s << v;
        return s.str();
      };
      if (fd.layers)
      {
        for (int s = 1; s <= 7; ++s)
        {
          Fluid f = water;
          f.spans = s;
          measured.push_back(fluidRow("sph-voxel-spans-" + std::to_string(s), "", f, ""));
        }
        // The error that remains is the layers' quantization of the sheets' depths: it
        // falls with the angle resolution (one span kept).
        for (const double a : { 28.0, 14.0, 7.0 })
        {
          Fluid f = water;
          f.spans = 1;
          f.angle = a;
          f.layers = 1 << 16;
          measured.push_back(fluidRow("sph-voxel-angle-" + label(a), "", f, ""));
        }
      }
      else
      {
        Fluid translucent = water;
        translucent.ior = 1;
        measured.push_back(fluidRow("sph-voxel", "", water, "smooth"));
        measured.push_back(fluidRow("sph-voxel-translucent", "", translucent, "smooth"));
        Fluid noCulling = water;
        noCulling.culling = false;
        measured.push_back(fluidRow("sph-voxel-noculling", "", noCulling, "smooth"));
        if (!fd.stageOnly)
        {
          for (const double a : { 28.0, 14.0, 7.0 })
          {
            Fluid f = plain;
            f.angle = a;
            f.layers = 1 << 17;
            measured.push_back(fluidRow("sph-voxel-angle-" + label(a), "", f, "plain"));
          }
          for (int s = 1; s <= 7; ++s)
          {
            Fluid f = water;
            f.spans = s;
            measured.push_back(fluidRow("sph-voxel-spans-" + std::to_string(s), "", f, "smooth"));
          }
          for (const int it : { 0, 2, 5, 10, 20, 40, 80 })
          {
            Fluid f = water;
            f.smoothIterations = it;
            measured.push_back(fluidRow("sph-voxel-smooth-" + std::to_string(it), "", f, "smooth"));
          }
        }
      }

      // The contour route.
      struct Contour
      {
        Method method;
        std::function<void(vtkRenderer*)> inspect;
        std::shared_ptr<Resampled> grid;
        std::shared_ptr<double> contourMs;
        std::shared_ptr<FluidLog> log;
        std::shared_ptr<Surface> surface;
      };
      std::vector<Contour> contours;
      if (!fd.layers && !fd.stageOnly)
      {
        for (const int res : { 64, 128, 256 })
        {
          Contour c;
          c.grid = std::make_shared<Resampled>();
          c.contourMs = std::make_shared<double>(0);
          c.log = std::make_shared<FluidLog>();
          c.surface = std::make_shared<Surface>();
          auto grid = c.grid;
          auto contourMs = c.contourMs;
          auto log = c.log;
          auto surface = c.surface;
          auto actor = std::make_shared<vtkSmartPointer<vtkActor>>();
          c.method.name = "sph-contour-surface-grid" + std::to_string(res);
          c.method.setting = "grid=" + std::to_string(res) + ";iso=0.5";
          const Fluid look = water;
          c.method.setup = [&fd, &resampled, grid, contourMs, log, actor, look, res](
                             vtkRenderer* ren)
          {
            auto it = resampled.find(res);
            if (it == resampled.end())
            {
              it = resampled.emplace(res, std::make_shared<Resampled>(Resample(fd.source, res))).first;
            }
            *grid = *it->second;
            const double t0 = Now();
            vtkNew<vtkContourFilter> contour;
            contour->SetInputData(grid->image);
            contour->SetInputArrayToProcess(
              0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, "Shepard Summation");
            contour->SetValue(0, 0.5);
            contour->ComputeNormalsOn();
            contour->ComputeScalarsOff();
            contour->Update();
            *contourMs = Now() - t0;
            vtkNew<vtkPolyDataMapper> mapper;
            mapper->SetInputConnection(contour->GetOutputPort());
            mapper->ScalarVisibilityOff();
            auto a = vtkSmartPointer<vtkActor>::New();
            a->SetMapper(mapper);
            a->GetProperty()->SetColor(look.color[0], look.color[1], look.color[2]);
            a->GetProperty()->SetAmbient(look.ambient);
            a->GetProperty()->SetDiffuse(look.diffuse);
            a->GetProperty()->SetSpecular(look.specular);
            a->GetProperty()->SetSpecularPower(look.specularPower);
            ren->AddActor(a);
            *actor = a;
            log->Attach(ren); // frame times only (no fluid mapper)
          };
          c.method.buildMs = [grid, contourMs]() { return grid->ms + *contourMs; };
          c.method.buildDetail = [grid, contourMs]()
          {
            const int* dims = grid->image->GetDimensions();
            std::ostringstream s;
            s << "resample " << grid->ms << " ms onto " << dims[0] << "x" << dims[1] << "x"
              << dims[2] << " (spacing " << grid->spacing << "), contour " << *contourMs << " ms";
            return s.str();
          };
          c.inspect = [surface, actor](vtkRenderer* ren)
          { *surface = WindowSurface(ren, *actor); };
          contours.push_back(c);
        }
      }

      // The references a selected row is compared with.
      std::map<std::string, Row3> references;
      auto needs = [&](const std::string& key)
      {
        return std::any_of(measured.begin(), measured.end(),
                 [&](const Row3& o)
                 {
                   return o.reference == key && Wanted(opt, o.method, fd.layers) &&
                     o.method.name != "sph-voxel" && o.method.name != "sph-voxel-translucent";
                 }) ||
          (key == "plain" &&
            std::any_of(contours.begin(), contours.end(),
              [&](const Contour& c) { return Wanted(opt, c.method, fd.layers); }));
      };
      std::map<std::string, Result> referenceResults;
      for (const auto& [key, f] : { std::make_pair(std::string("plain"), reference),
             std::make_pair(std::string("smooth"), smoothReference) })
      {
        if (fd.layers || fd.stageOnly || !opt.references || !needs(key))
        {
          continue;
        }
        Row3 ref = fluidRow("sph-voxel-reference", "", f, "");
        ref.method.repeat = 1;
        ref.method.touch = nullptr; // one frame after the first, no rebuilds
        measured.insert(measured.begin(), ref);
        references.emplace(key, ref);
      }

      // Measure: the references first (inserted at the front), then the rows.
      for (const Row3& o : measured)
      {
        const bool isReference = o.method.name == "sph-voxel-reference";
        if (!isReference && !Wanted(opt, o.method, fd.layers))
        {
          continue;
        }
        Result r = Measure(opt, o.method, camera, o.inspect);
        r.row.suite = "sph";
        r.row.dataset = dataset;
        r.row.items = n;
        vtkRayMapperStatistics* st = (*o.mapper)->GetStatistics();
        VoxelExtra e;
        for (int k = 0; k < FluidLog::N; ++k)
        {
          e.phaseMs[k] = o.log->Later(k);
        }
        // The render phase is either translucent ("render") or refraction ("refract").
        const bool refract = o.fluid.ior != 1;
        e.phaseMs[refract ? 6 : 7] = -1;
        e.layers = st->GetCounter("layers");
        e.spansFound = st->GetCounter("spans_found");
        e.spansStored = st->GetCounter("spans_stored");
        e.tiles = st->GetCounter("tiles");
        e.filterIterations = st->GetCounter("filter_iterations");
        e.angleDeg = o.surface->angleReached;
        r.row.memMb = st->GetCounter("peak_temporary_bytes") / 1048576.0;
        if (isReference)
        {
          for (const auto& [key, ref] : references)
          {
            if (ref.surface == o.surface)
            {
              referenceResults[key] = r;
            }
          }
        }
        else if (fd.layers)
        {
          LayersError(r.image, *o.surface, r, e.thicknessRelErr);
        }
        else
        {
          auto ref = references.find(o.reference);
          if (ref != references.end())
          {
            // Images of the same look only (translucency alone is not the refracting
            // reference's picture); surfaces always.
            if (ref->second.fluid.ior == o.fluid.ior)
            {
              Compare(referenceResults[o.reference].image, r.image, r.row.rmse, r.row.maxErr);
            }
            e.error = CompareSurfaces(*o.surface, *ref->second.surface);
          }
        }
        FrameTimes times;
        times.frameMs = r.row.buildMs + r.row.renderMs;
        times.firstFrameMs = o.log->frameMs.empty() ? -1 : o.log->frameMs[0];
        std::cout << "  " << dataset << " " << o.method.name << " " << o.method.setting
                  << ": frame " << r.row.renderMs << " ms (splat " << e.phaseMs[0]
                  << ", compress " << e.phaseMs[1] << ", connect " << e.phaseMs[2]
                  << ", filter " << e.phaseMs[3] << ", normals " << e.phaseMs[4] << ", render "
                  << (refract ? e.phaseMs[7] : e.phaseMs[6]) << "), " << e.layers
                  << " layers (angle " << e.angleDeg << "), " << e.tiles << " tiles, peak "
                  << r.row.memMb << " MB, spans " << st->GetCounter("spans_bytes") / 1048576.0
                  << " MB; work: " << st->GetCounter("splat_pixels")
                  << " splat pixels, " << st->GetCounter("boxes_in_view") << " boxes on "
                  << st->GetCounter("box_pixels") << " pixels, " << st->GetCounter("set_bit_ops")
                  << " bit-set ops, "
                  << st->GetCounter("refraction_paths") << " paths, "
                  << st->GetCounter("march_columns") << " march steps ("
                  << st->GetCounter("march_tile_skips") << " tiles)"
                  << (e.error.meanAbs >= 0 ? ", depth |d| " + Number(e.error.meanAbs) +
                          ", coverage diff " + Number(e.error.coverage)
                                           : "")
                  << (r.row.rmse >= 0 ? ", rmse " + Number(r.row.rmse) : "")
                  << (e.thicknessRelErr >= 0 ? ", thickness rel err " + Number(e.thicknessRelErr)
                                             : "")
                  << std::endl;
        RecordVoxelRow(opt, r, times, e.Csv(), rows);
        if (o.method.name == "sph-voxel" || o.method.name == "sph-voxel-translucent")
        {
          auto at = std::find_if(stages.begin(), stages.end(),
            [&](const Stage& s) { return s.dataset == dataset && s.width == opt.width; });
          if (at == stages.end())
          {
            stages.push_back(Stage());
            at = stages.end() - 1;
            at->dataset = dataset;
            at->width = opt.width;
            at->height = opt.height;
            at->particles = n;
          }
          at->inView = st->GetCounter("particles_in_view");
          if (refract || at->refractMs < 0)
          {
            at->ms = e.phaseMs; // the voxelization's stages: the water look's when measured
          }
          if (refract)
          {
            at->refractMs = e.phaseMs[7];
            at->memMb = r.row.memMb;
          }
          else
          {
            at->translucentMs = e.phaseMs[6];
          }
        }
      }
      for (const Contour& c : contours)
      {
        if (!Wanted(opt, c.method, fd.layers))
        {
          continue;
        }
        Result r = Measure(opt, c.method, camera, c.inspect);
        r.row.suite = "sph";
        r.row.dataset = dataset;
        r.row.items = n;
        VoxelExtra e;
        e.contourMs = *c.contourMs;
        auto ref = references.find("plain");
        if (ref != references.end())
        {
          e.error = CompareSurfaces(*c.surface, *ref->second.surface);
        }
        FrameTimes times;
        times.resampleMs = c.grid->ms;
        times.firstFrameMs = c.log->frameMs.empty() ? -1 : c.log->frameMs[0];
        times.frameMs = c.grid->ms + e.contourMs + times.firstFrameMs;
        std::cout << "  " << dataset << " " << c.method.name << ": resample " << c.grid->ms
                  << " ms, contour " << e.contourMs << " ms, first frame " << times.firstFrameMs
                  << " ms"
                  << (e.error.meanAbs >= 0 ? ", depth |d| " + Number(e.error.meanAbs) +
                          ", bias " + std::to_string(e.error.bias) + ", coverage diff " +
                          Number(e.error.coverage)
                                           : "")
                  << std::endl;
        RecordVoxelRow(opt, r, times, e.Csv(), rows);
      }
    }
  }
  PrintStageTable(stages);
  return rows;
}

} // namespace sph
} // namespace bench
