// The sph suite: vtkSPHVolumeMapper on PySPH dam break frames against what a VTK or ParaView
// user does today, resampling the particles onto an image grid with vtkSPHInterpolator (the
// same Wendland C2 kernel, support 2h, V = m / rho, Shepard normalized: the same field) and
// ray casting the grid with vtkFixedPointVolumeRayCastMapper, at several grid sizes.
//
// Data: Data/dam_break_coarse_00674.vtk (9,360 particles, t = 0.3 s) and, when the generator
// has made them, the build/data/dam_break_fine_*.vtk time step closest to t = 0.3 s
// (>= 200,000 particles); --data takes other legacy particle files: PySPH's h, m, rho and
// vmag, or the arrays raymappers-bench.cxx's header says are chosen instead (--array, --h).
// Two views each at --size: outside (the whole fluid from the side and above) and surface
// (the camera close to the free surface of the collapsing column, part of the fluid in view).
//
// Methods (the CSV's method column):
//   reference                the mapper at StepFactor 0.25 and SamplesPerSupport 64 (the
//                            step is the longer of the pixel's footprint times StepFactor
//                            and the smallest support over SamplesPerSupport: a quarter and
//                            an eighth of the defaults) without early termination: the converged
//                            image of each effect setting (normalized, and one per effect
//                            below); its time is reported too
//   sph-raycast              the mapper's defaults (normalized, step 1, samples per support 8,
//                            tile 16, slab 0 = a cell's samples, termination 0.99)
//   sph-interpolator-volume  resample (grid=N voxels along the longest axis, sample distance
//                            half a voxel) + VTK's CPU ray caster, same transfer functions,
//                            unit distance, camera, window and background
//   sph-unnormalized, sph-pseudo, sph-gradient, sph-contour
//                            one effect each (Limper 2012, table 4.4), compared with the
//                            reference of the same effect
//   sph-step-F, sph-sps-N, sph-slab-D, sph-tile-T, sph-ert-O
//                            one parameter of sph-raycast changed (StepFactor,
//                            SamplesPerSupport, SlabDepth, TileSize, TerminationOpacity)
// The suite's CSV has the common columns and then SPHCsvExtraColumns:
//   frame_ms        a new time step shown: build_ms (our particle rebuild; the resample) plus
//                   render_ms for our mapper, resample + first frame for the interpolator
//                   (VTK's ray caster prepares its volume in the first frame)
//   resample_ms     vtkSPHInterpolator and the null-voxel mask (empty for ours)
//   first_frame_ms  the first frame after the data changed (window render)
//   grid_ms, raycast_ms                           our phases, median over the timed frames
//   grid_mb                                       our perspective grid's memory
//   kernel_evaluations, weight_sums, gradient_evaluations, samples, contour_samples
//                                                 our counters of one frame (the kernel
//                                                 counters count SIMD lanes, 16 per chunk)
// then the fluid half's columns (SPHVoxelSuite.cxx: vtkSPHFluidMapper, methods sph-voxel*
// and sph-contour-surface-grid*, run after these on the same files), empty in these rows.
#include "BenchData.h"
#include "BenchRun.h"
#include "SPHSuite.h"
#include "vtkRayMapperStatistics.h"
#include "vtkSPHVolumeMapper.h"

#include "vtkCallbackCommand.h"
#include "vtkCamera.h"
#include "vtkColorTransferFunction.h"
#include "vtkCommand.h"
#include "vtkDataArray.h"
#include "vtkFixedPointVolumeRayCastMapper.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkPolyDataReader.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkSMPTools.h"
#include "vtkSPHInterpolator.h"
#include "vtkSmartPointer.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"
#include "vtkWendlandQuinticKernel.h"
#include "vtksys/Directory.hxx"
#include "vtksys/SystemTools.hxx"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

namespace bench
{

extern const char* const SPHCsvExtraColumns; // declared in raymappers-bench.cxx
namespace
{
const std::string ExtraColumns =
  std::string("frame_ms,resample_ms,first_frame_ms,grid_ms,raycast_ms,grid_mb,"
              "kernel_evaluations,weight_sums,gradient_evaluations,samples,contour_samples,") +
  sph::VoxelCsvColumns;
}
const char* const SPHCsvExtraColumns = ExtraColumns.c_str();

namespace sph
{
namespace
{
// The simulated time "t = X s" in a PySPH legacy file's title line, -1 if there is none.
double TitleTime(const std::string& file)
{
  std::ifstream in(file);
  std::string line;
  std::getline(in, line); // "# vtk DataFile Version 3.0"
  std::getline(in, line);
  const std::size_t at = line.find("t = ");
  return at == std::string::npos ? -1.0 : std::atof(line.c_str() + at + 4);
}
} // namespace

namespace
{
// The smoothing length and the value of `d.particles`: --h, else an h-like array (a radius
// array too), else 1.2 x the typical spacing (Wendland C2's support 2h then reaches 2.4
// spacings: the neighbours SPH codes keep); the value as ChooseValueArray picks it, a speed
// first. False when --array names no point array of the file.
bool ChooseArrays(Dataset& d, const Options& opt)
{
  d.smoothing = ChooseSize(d.particles, vtkRayMapperParticleSizes::Role::SmoothingLength, true,
    SPHSmoothingPerSpacing, opt.h);
  double range[2] = { d.smoothing.constant, d.smoothing.constant };
  if (!d.smoothing.array.empty())
  {
    d.particles->GetPointData()->GetArray(d.smoothing.array.c_str())->GetRange(range, 0);
  }
  d.h = d.smoothing.scale * range[1];
  vtkDataArray* value = nullptr;
  if (!ChooseValueArray(d.particles, opt.array, d.file, true, value) || !value)
  {
    if (!value && opt.array.empty())
    {
      std::cerr << "sph: " << d.file << " has no 1-component point array to sample; its point "
                << "arrays: " << ListPointArrays(d.particles) << "\n";
    }
    return false;
  }
  d.value = value->GetName();
  value->GetRange(range, 0);
  d.vmax = range[1] > 0 ? range[1] : 1.0;
  return true;
}

// The mass and density arrays (m or mass, rho or density, ignoring case). A file without
// both gets a constant mass s^3 (s the typical spacing) and density 1, so that every method
// still runs: the normalized rows do not depend on V, the unnormalized rows and the
// interpolator's Shepard sum (the contour route's volume fraction) use V = s^3.
void ChooseVolume(Dataset& d)
{
  vtkDataArray* mass = FindNamedArray(d.particles, { "m", "mass" }, 1);
  vtkDataArray* density = FindNamedArray(d.particles, { "rho", "density" }, 1);
  if (mass && density)
  {
    d.mass = mass->GetName();
    d.density = density->GetName();
    return;
  }
  vtkRayMapperParticleSizes::SpacingCache cache;
  const double s = vtkRayMapperParticleSizes::AutomaticLength(d.particles, 1.0, cache);
  const vtkIdType n = d.particles->GetNumberOfPoints();
  d.mass = "mass_from_spacing";
  d.density = "unit_density";
  for (const auto& [name, v] :
    { std::make_pair(d.mass, s * s * s), std::make_pair(d.density, 1.0) })
  {
    vtkNew<vtkFloatArray> a;
    a->SetName(name.c_str());
    a->SetNumberOfTuples(n);
    a->FillValue(static_cast<float>(v));
    d.particles->GetPointData()->AddArray(a);
  }
  std::cout << "sph: " << d.file << " has no "
            << (mass ? "density (rho, density)" : "mass (m, mass)")
            << " point array: particle volume V = s^3 = " << s * s * s
            << " from the typical spacing s = " << s
            << " (the unnormalized rows and the Shepard sum use it)\n";
}
} // namespace

Dataset Load(const std::string& file, const Options& opt)
{
  Dataset d;
  d.file = file;
  d.name = BaseName(file);
  d.time = TitleTime(file);
  if (!vtksys::SystemTools::FileExists(file, true))
  {
    std::cerr << "sph: no such file: " << file << "\n";
    return d;
  }
  vtkNew<vtkPolyDataReader> reader;
  reader->SetFileName(file.c_str());
  reader->ReadAllScalarsOn(); // one SCALARS section per array
  reader->ReadAllVectorsOn();
  reader->Update();
  d.particles = vtkSmartPointer<vtkPolyData>::New();
  d.particles->ShallowCopy(reader->GetOutput());
  if (d.particles->GetNumberOfPoints() == 0 || !ChooseArrays(d, opt))
  {
    d.particles = nullptr;
    return d;
  }
  ChooseVolume(d);
  std::cout << "sph: " << d.name << ": smoothing length " << d.smoothing.how << ", value '"
            << d.value << "', V = " << d.mass << " / " << d.density << "\n";
  return d;
}

std::vector<std::string> DefaultFiles(const Options& opt)
{
  std::vector<std::string> files = { std::string(RAYMAPPERS_SOURCE_DIR) +
    "/Data/dam_break_coarse_00674.vtk" };
  vtksys::Directory dir;
  std::string best;
  double bestGap = 1e30;
  if (dir.Load(opt.generated))
  {
    for (unsigned long i = 0; i < dir.GetNumberOfFiles(); ++i)
    {
      const std::string name = dir.GetFile(i);
      if (name.rfind("dam_break_fine_", 0) != 0 || name.size() < 4 ||
        name.compare(name.size() - 4, 4, ".vtk") != 0 || name.find("walls") != std::string::npos)
      {
        continue;
      }
      const std::string path = opt.generated + "/" + name;
      const double t = TitleTime(path);
      const double gap = t > 0 ? std::fabs(t - 0.3) : 1e20; // t = 0: the fluid is at rest
      if (gap < bestGap)
      {
        bestGap = gap;
        best = path;
      }
    }
  }
  if (!best.empty())
  {
    files.push_back(best);
  }
  else
  {
    std::cout << "sph: no " << opt.generated
              << "/dam_break_fine_*.vtk yet (Data/Generators/pysph_dam_break.sh PREFIX 0.0148); "
                 "coarse data only\n";
  }
  return files;
}

namespace
{
// TestSPHVolumeMapper's transfer function scaled to the data's largest speed: blue through
// white to red, opacity 0.15 to 0.6 per 0.1 m. Below 0 (only the interpolator's null voxels,
// set to -vmax/2) the opacity is 0, so that the grid's empty voxels stay empty as the
// mapper's samples without neighbours do; the colour table, and so the range our mapper
// samples, is [0, vmax].
vtkSmartPointer<vtkVolumeProperty> MakeProperty(double vmax)
{
  auto property = vtkSmartPointer<vtkVolumeProperty>::New();
  vtkNew<vtkColorTransferFunction> color;
  color->AddRGBPoint(0.0, 0.1, 0.3, 0.9);
  color->AddRGBPoint(0.5 * vmax, 0.9, 0.9, 0.9);
  color->AddRGBPoint(vmax, 0.9, 0.2, 0.1);
  vtkNew<vtkPiecewiseFunction> opacity;
  opacity->AddPoint(-vmax, 0.0);
  opacity->AddPoint(-1e-4 * vmax, 0.0);
  opacity->AddPoint(0.0, 0.15);
  opacity->AddPoint(vmax, 0.6);
  property->SetColor(color);
  property->SetScalarOpacity(opacity);
  property->SetScalarOpacityUnitDistance(0.1);
  property->SetInterpolationTypeToLinear();
  property->SetAmbient(0.3); // for the gradient-shading effect (as the rendering test)
  property->SetDiffuse(0.7);
  return property;
}

// What a window observer records of every frame: its time and our mapper's phases.
struct FrameLog
{
  double t0 = 0;
  std::vector<double> frameMs, gridMs, raycastMs, particlesMs;
  vtkSPHVolumeMapper* mapper = nullptr;

  static void Start(vtkObject*, unsigned long, void* self, void*)
  {
    static_cast<FrameLog*>(self)->t0 = Now();
  }
  static void End(vtkObject*, unsigned long, void* self, void*)
  {
    auto* log = static_cast<FrameLog*>(self);
    log->frameMs.push_back(Now() - log->t0);
    if (log->mapper)
    {
      vtkRayMapperStatistics* st = log->mapper->GetStatistics();
      log->gridMs.push_back(st->GetPhaseTime("grid"));
      log->raycastMs.push_back(st->GetPhaseTime("raycast"));
      log->particlesMs.push_back(st->GetPhaseTime("particles"));
    }
  }
  void Attach(vtkRenderer* ren)
  {
    vtkRenderWindow* win = ren->GetRenderWindow();
    vtkNew<vtkCallbackCommand> start, end;
    start->SetCallback(&FrameLog::Start);
    start->SetClientData(this);
    end->SetCallback(&FrameLog::End);
    end->SetClientData(this);
    win->AddObserver(vtkCommand::StartEvent, start);
    win->AddObserver(vtkCommand::EndEvent, end);
  }
  // The median of a phase over the frames after the first.
  static double Later(const std::vector<double>& v)
  {
    return v.size() > 1 ? Median(std::vector<double>(v.begin() + 1, v.end()))
                        : (v.empty() ? -1.0 : v[0]);
  }
};

// Our mapper's settings.
struct Settings
{
  int normalization = VTK_SPH_NORMALIZED;
  bool shade = false;
  bool contour = false;
  double step = 1.0;
  double sps = 8.0; // SamplesPerSupport
  int tile = 16;
  int slab = 0;
  double ert = 0.99;
};

// The extra columns of one row.
struct Extra
{
  double frameMs = -1, resampleMs = -1, firstFrameMs = -1, gridMs = -1, raycastMs = -1,
         gridMb = -1;
  long long kernelEvaluations = -1, weightSums = -1, gradientEvaluations = -1, samples = -1,
            contourSamples = -1;
};

} // namespace

std::string Number(double v)
{
  if (v < 0)
  {
    return "";
  }
  std::ostringstream s;
  s << v;
  return s.str();
}

std::string Count(long long v)
{
  return v < 0 ? "" : std::to_string(v);
}

namespace
{
// Records the row (table, images) and appends it with the extra columns to --csv.
void RecordSPH(const Options& opt, const Result& r, const Extra& e, std::vector<Row>& rows)
{
  Options noCsv = opt;
  noCsv.csv.clear();
  Record(noCsv, r, rows);
  std::cout << "  " << r.row.dataset << " " << r.row.method << " " << r.row.setting << ": render "
            << r.row.renderMs << " ms, build " << r.row.buildMs << " ms, frame " << e.frameMs
            << " ms" << (e.resampleMs >= 0 ? ", resample " + Number(e.resampleMs) + " ms" : "")
            << (e.gridMs >= 0 ? ", grid " + Number(e.gridMs) + " ms, raycast " +
                    Number(e.raycastMs) + " ms, kernel evaluations " +
                    Count(e.kernelEvaluations) + ", gradients " + Count(e.gradientEvaluations)
                              : "")
            << (r.row.rmse >= 0 ? ", rmse " + Number(r.row.rmse * 255.0) + "/255, max " +
                    Number(r.row.maxErr * 255.0) + "/255"
                                : "")
            << std::endl;
  if (!opt.csv.empty())
  {
    std::ofstream out(opt.csv, std::ios::app);
    out << Csv(r.row) << "," << Number(e.frameMs) << "," << Number(e.resampleMs) << ","
        << Number(e.firstFrameMs) << "," << Number(e.gridMs) << "," << Number(e.raycastMs) << ","
        << Number(e.gridMb) << "," << Count(e.kernelEvaluations) << "," << Count(e.weightSums) << ","
        << Count(e.gradientEvaluations) << "," << Count(e.samples) << ","
        << Count(e.contourSamples) << "," << EmptyVoxelCsv() << std::endl;
  }
}
} // namespace

void RecordVoxelRow(const Options& opt,
  const Result& r,
  const FrameTimes& times,
  const std::string& voxelCsv,
  std::vector<Row>& rows)
{
  Options noCsv = opt;
  noCsv.csv.clear();
  Record(noCsv, r, rows);
  if (!opt.csv.empty())
  {
    std::ofstream out(opt.csv, std::ios::app);
    out << Csv(r.row) << "," << Number(times.frameMs) << "," << Number(times.resampleMs) << ","
        << Number(times.firstFrameMs) << std::string(9, ',') // grid_ms ... contour_samples
        << voxelCsv << std::endl;
  }
}

// vtkSPHInterpolator onto a grid of `res` voxels along the longest side of the particles'
// bounds grown by the support, only the value interpolated (the fastest the filter goes), then
// the voxels without a neighbour (Shepard sum 0, which ShepardNormalization sets to 0) set
// to -vmax/2, below the transfer function's visible range. The Shepard sum is kept beside
// (the array itself, not a copy).
Resampled Resample(const Dataset& d, int res)
{
  Resampled out;
  const double t0 = Now();
  double b[6];
  d.particles->GetBounds(b);
  const double grow = 2.0 * d.h;
  double longest = 0;
  for (int a = 0; a < 3; ++a)
  {
    b[2 * a] -= grow;
    b[2 * a + 1] += grow;
    longest = std::max(longest, b[2 * a + 1] - b[2 * a]);
  }
  const double s = longest / (res - 1);
  vtkNew<vtkImageData> grid;
  grid->SetOrigin(b[0], b[2], b[4]);
  grid->SetSpacing(s, s, s);
  grid->SetDimensions(std::max(2, int(std::ceil((b[1] - b[0]) / s)) + 1),
    std::max(2, int(std::ceil((b[3] - b[2]) / s)) + 1),
    std::max(2, int(std::ceil((b[5] - b[4]) / s)) + 1));

  vtkNew<vtkWendlandQuinticKernel> kernel; // (1 - q/2)^4 (1 + 2q), q = r / h: support 2h
  kernel->SetSpatialStep(d.h);             // the largest h (PySPH's is constant)
  kernel->SetDimension(3);
  vtkNew<vtkSPHInterpolator> interpolator;
  interpolator->SetInputData(grid);
  interpolator->SetSourceData(d.particles);
  interpolator->SetKernel(kernel);
  interpolator->SetMassArrayName(d.mass);
  interpolator->SetDensityArrayName(d.density);
  interpolator->ShepardNormalizationOn();
  interpolator->SetNullPointsStrategyToNullValue();
  interpolator->SetNullValue(0.0);
  vtkPointData* pd = d.particles->GetPointData();
  for (int i = 0; i < pd->GetNumberOfArrays(); ++i)
  {
    const char* name = pd->GetArrayName(i);
    if (name && name != d.value)
    {
      interpolator->AddExcludedArray(name);
    }
  }
  interpolator->Update();
  vtkImageData* result = vtkImageData::SafeDownCast(interpolator->GetOutput());
  vtkDataArray* value = result->GetPointData()->GetArray(d.value.c_str());
  vtkDataArray* shepard = result->GetPointData()->GetArray("Shepard Summation");
  vtkNew<vtkFloatArray> scalars;
  scalars->SetName(d.value.c_str());
  scalars->SetNumberOfTuples(result->GetNumberOfPoints());
  const float empty = static_cast<float>(-0.5 * d.vmax);
  for (vtkIdType i = 0; i < result->GetNumberOfPoints(); ++i)
  {
    scalars->SetValue(i,
      shepard->GetComponent(i, 0) > 0 ? static_cast<float>(value->GetComponent(i, 0)) : empty);
  }
  out.image = vtkSmartPointer<vtkImageData>::New();
  out.image->CopyStructure(result);
  out.image->GetPointData()->SetScalars(scalars);
  out.image->GetPointData()->AddArray(shepard);
  out.ms = Now() - t0;
  out.spacing = s;
  return out;
}

// The views: "outside" as TestSPHVolumeMapper (from the side and above, z up) with the whole
// fluid in the square window; "surface" close to the free surface where the column's flow
// accelerates.
std::function<void(vtkCamera*)> View(const Dataset& d, const std::string& view)
{
  double bounds[6];
  d.particles->GetBounds(bounds);
  return [b0 = std::vector<double>(bounds, bounds + 6), view](vtkCamera* cam)
  {
    const double* b = b0.data();
    cam->SetViewUp(0, 0, 1);
    cam->SetViewAngle(30);
    if (view == "outside")
    {
      const double c[3] = { 0.5 * (b[0] + b[1]), 0.5 * (b[2] + b[3]), b[4] + 0.35 * (b[5] - b[4]) };
      const double dir[3] = { -0.7, -2.6, 1.3 }; // the test's camera from its focal point
      const double len = std::sqrt(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
      const double dist = 2.7 * (b[1] - b[0]); // 4.6 m for the 1.7 m long flow at 0.3 s
      cam->SetFocalPoint(c);
      cam->SetPosition(
        c[0] + dist * dir[0] / len, c[1] + dist * dir[1] / len, c[2] + dist * dir[2] / len);
    }
    else
    {
      // The free surface where the collapsing column accelerates into the surge (at 0.3 s
      // x = 1.26 m, z = 0.31 m: white turning red), seen from 0.62 m above and behind it:
      // about a third of a metre of the surface fills the view.
      const double f[3] = { b[0] + 0.72 * (b[1] - b[0]), 0.5 * (b[2] + b[3]),
        b[4] + 0.6 * (b[5] - b[4]) };
      cam->SetFocalPoint(f);
      cam->SetPosition(f[0] - 0.25, f[1] - 0.45, f[2] + 0.35);
    }
  };
}
} // namespace sph

std::vector<Row> RunSPH(const Options& opt)
{
  using namespace sph;
  // vtkSPHInterpolator runs on vtkSMPTools; this VTK's default backend is Sequential: the
  // resample gets both cores (std::thread) as our mapper does with TBB.
  vtkSMPTools::SetBackend("STDThread");
  vtkSMPTools::Initialize(opt.threads);
  std::cout << "vtkSMPTools backend " << vtkSMPTools::GetBackend() << ", "
            << vtkSMPTools::GetEstimatedNumberOfThreads() << " threads\n";
  WarmUp(opt);
  const std::vector<std::string> files = opt.data.empty() ? DefaultFiles(opt) : opt.data;
  std::vector<Row> rows;
  for (const std::string& file : files)
  {
    if (!vtksys::SystemTools::FileExists(file, true))
    {
      continue; // the voxel half's synthetic and refined sets (or a missing file: it says so)
    }
    const Dataset d = Load(file, opt);
    if (!d.particles || d.particles->GetNumberOfPoints() == 0)
    {
      continue;
    }
    const long long n = d.particles->GetNumberOfPoints();
    const auto property = MakeProperty(d.vmax);
    auto shaded = vtkSmartPointer<vtkVolumeProperty>::New();
    shaded->DeepCopy(property);
    shaded->ShadeOn();
    std::cout << d.name << ": " << n << " particles, t = " << d.time << " s, h " << d.h
              << ", " << d.value << " up to " << d.vmax << "\n";
    std::map<int, Resampled> resampled; // by grid size, shared by the views

    for (const std::string view : { "outside", "surface" })
    {
      if (!ViewSelected(opt, view))
      {
        continue;
      }
      const auto camera = View(d, view);
      const std::string dataset = d.name + "-" + view;

      // Our mapper with settings s; the log collects its frames.
      struct Ours
      {
        Method method;
        std::shared_ptr<FrameLog> log;
        std::shared_ptr<vtkSmartPointer<vtkSPHVolumeMapper>> mapper;
        std::string reference; // the reference it is compared with
      };
      auto ours = [&](const std::string& name, const std::string& setting, const Settings& s,
                    const std::string& reference, bool touch = false)
      {
        Ours o;
        o.log = std::make_shared<FrameLog>();
        o.mapper = std::make_shared<vtkSmartPointer<vtkSPHVolumeMapper>>();
        o.reference = reference;
        auto log = o.log;
        auto mapper = o.mapper;
        vtkVolumeProperty* prop = s.shade ? shaded.Get() : property.Get();
        o.method.name = name;
        o.method.setting = setting;
        o.method.setup = [&d, log, mapper, s, prop](vtkRenderer* ren)
        {
          auto m = vtkSmartPointer<vtkSPHVolumeMapper>::New();
          m->SetInputData(d.particles);
          m->SetKernel(VTK_SPH_KERNEL_WENDLAND_C2);
          m->SetScaleArray(d.smoothing.array.empty() ? nullptr : d.smoothing.array.c_str());
          m->SetScaleFactor(d.smoothing.scale);
          m->SetSmoothingLength(d.smoothing.constant > 0 ? d.smoothing.constant : 1.0);
          m->SetMassArrayName(d.mass.c_str());
          m->SetDensityArrayName(d.density.c_str());
          m->SetValueArrayName(d.value.c_str());
          m->SetNormalization(s.normalization);
          m->SetContourShading(s.contour);
          m->SetStepFactor(s.step);
          m->SetSamplesPerSupport(s.sps);
          m->SetTileSize(s.tile);
          m->SetSlabDepth(s.slab);
          m->SetTerminationOpacity(s.ert);
          vtkNew<vtkVolume> volume;
          volume->SetMapper(m);
          volume->SetProperty(prop);
          ren->AddVolume(volume);
          *mapper = m;
          log->mapper = m;
          log->Attach(ren);
        };
        o.method.buildMs = [mapper]()
        { return (*mapper)->GetStatistics()->GetPhaseTime("particles"); };
        if (touch)
        {
          o.method.touch = [&d]() { d.particles->Modified(); };
        }
        o.method.buildDetail = [mapper]()
        {
          vtkRayMapperStatistics* st = (*mapper)->GetStatistics();
          std::ostringstream out;
          out << "particles " << st->GetPhaseTime("particles") << " ms, grid "
              << st->GetPhaseTime("grid") << " ms (" << st->GetCounter("grid_cells") << " cells, "
              << st->GetCounter("grid_bytes") / 1048576.0 << " MB, "
              << st->GetCounter("particles_in_view") << " particles in view), raycast "
              << st->GetPhaseTime("raycast") << " ms, draw " << st->GetPhaseTime("draw")
              << " ms; cells visited " << st->GetCounter("cells_visited") << ", leaped "
              << st->GetCounter("cells_leaped") << ", samples " << st->GetCounter("samples")
              << ", terminated rays " << st->GetCounter("terminated_rays");
          return out.str();
        };
        return o;
      };

      // The references (step 0.25, no early termination) and what is compared with them.
      // StepFactor 0.25 alone no longer refines: SamplesPerSupport (default 8) makes the
      // step at least the smallest support / 8. The reference takes StepFactor 0.25 and 64
      // samples per support (an eighth of the default step; a quarter, 32, still differed
      // from pixel-tied steps by 0.3/255 rmse on the coarse data at 1024x1024).
      const Settings fine{ VTK_SPH_NORMALIZED, false, false, 0.25, 64.0, 16, 0, 1.0 };
      auto with = [](Settings s, auto change)
      {
        change(s);
        return s;
      };
      struct Group
      {
        std::string key;
        Settings reference;
        std::vector<Ours> methods;
      };
      std::vector<Group> groups;
      Group normalized{ "normalized", fine, {} };
      normalized.methods.push_back(ours("sph-raycast", "default", Settings(), "normalized", true));
      groups.push_back(normalized);
      const std::vector<std::tuple<std::string, std::string, std::function<void(Settings&)>>>
        effects = {
          { "unnormalized", "normalization=unnormalized",
            [](Settings& s) { s.normalization = VTK_SPH_UNNORMALIZED; } },
          { "pseudo", "normalization=pseudo",
            [](Settings& s) { s.normalization = VTK_SPH_PSEUDO_NORMALIZED; } },
          { "gradient", "shade=on", [](Settings& s) { s.shade = true; } },
          { "contour", "contour=on", [](Settings& s) { s.contour = true; } },
        };
      for (const auto& [key, setting, change] : effects)
      {
        Group g{ key, with(fine, change), {} };
        g.methods.push_back(ours("sph-" + key, setting, with(Settings(), change), key));
        groups.push_back(g);
      }
      // The sweeps of sph-raycast, against the normalized reference.
      auto label = [](double v)
      {
        std::ostringstream s;
        s << v;
        return s.str();
      };
      for (const double f : { 0.5, 1.0, 2.0, 4.0 })
      {
        groups[0].methods.push_back(ours("sph-step-" + label(f), "step=" + label(f),
          with(Settings(), [f](Settings& s) { s.step = f; }), "normalized"));
      }
      // SamplesPerSupport: the field-tied bound on the step (0: the thesis's pixel-tied steps
      // alone, only in the outside view: in the surface view a pixel is a fraction of a mm).
      for (const double sps : view == "outside" ? std::vector<double>{ 1, 2, 4, 8, 16, 32, 0 }
                                                : std::vector<double>{ 1, 2, 4, 8, 16, 32 })
      {
        groups[0].methods.push_back(ours("sph-sps-" + label(sps), "sps=" + label(sps),
          with(Settings(), [sps](Settings& s) { s.sps = sps; }), "normalized"));
      }
      for (const int slab : { 1, 4, 8, 0 })
      {
        groups[0].methods.push_back(ours("sph-slab-" + std::to_string(slab),
          "slab=" + std::to_string(slab) + (slab == 0 ? "(cell)" : ""),
          with(Settings(), [slab](Settings& s) { s.slab = slab; }), "normalized"));
      }
      for (const int tile : { 8, 16, 32 })
      {
        groups[0].methods.push_back(ours("sph-tile-" + std::to_string(tile),
          "tile=" + std::to_string(tile),
          with(Settings(), [tile](Settings& s) { s.tile = tile; }), "normalized"));
      }
      for (const double ert : { 0.9, 0.95, 0.99, 1.0 })
      {
        groups[0].methods.push_back(ours("sph-ert-" + label(ert), "ert=" + label(ert),
          with(Settings(), [ert](Settings& s) { s.ert = ert; }), "normalized"));
      }

      // The resampling route, grid sizes along the longest axis.
      std::vector<int> grids = { 32, 64, 128, 192, 256 };
      struct Theirs
      {
        Method method;
        std::shared_ptr<FrameLog> log;
        std::shared_ptr<Resampled> grid;
      };
      std::vector<Theirs> theirs;
      for (const int res : grids)
      {
        Theirs t;
        t.log = std::make_shared<FrameLog>();
        t.grid = std::make_shared<Resampled>();
        auto log = t.log;
        auto grid = t.grid;
        t.method.name = "sph-interpolator-volume";
        t.method.setting = "grid=" + std::to_string(res);
        t.method.setup = [&d, &resampled, &property, log, grid, res](vtkRenderer* ren)
        {
          auto it = resampled.find(res);
          if (it == resampled.end())
          {
            it = resampled.emplace(res, Resample(d, res)).first;
          }
          *grid = it->second;
          vtkNew<vtkFixedPointVolumeRayCastMapper> mapper;
          mapper->SetInputData(grid->image);
          mapper->SetSampleDistance(0.5 * grid->spacing);
          mapper->SetAutoAdjustSampleDistances(0);
          mapper->SetImageSampleDistance(1.0);
          vtkNew<vtkVolume> volume;
          volume->SetMapper(mapper);
          volume->SetProperty(property);
          ren->AddVolume(volume);
          log->Attach(ren);
        };
        t.method.buildMs = [grid]() { return grid->ms; };
        theirs.push_back(t);
      }

      // Measure: each group's reference when one of its methods is selected, then them.
      std::map<std::string, vtkSmartPointer<vtkImageData>> references;
      auto measureOurs = [&](const Ours& o, const std::string& referenceKey)
      {
        Result r = Measure(opt, o.method, camera);
        r.row.suite = "sph";
        r.row.dataset = dataset;
        r.row.items = n;
        auto ref = references.find(referenceKey);
        if (ref != references.end() && ref->second)
        {
          Compare(ref->second, r.image, r.row.rmse, r.row.maxErr);
        }
        vtkRayMapperStatistics* st = (*o.mapper)->GetStatistics();
        Extra e;
        e.gridMs = FrameLog::Later(o.log->gridMs);
        e.raycastMs = FrameLog::Later(o.log->raycastMs);
        e.firstFrameMs = o.log->frameMs.empty() ? -1 : o.log->frameMs[0];
        e.frameMs = r.row.buildMs + r.row.renderMs;
        e.gridMb = st->GetCounter("grid_bytes") / 1048576.0;
        e.kernelEvaluations = st->GetCounter("kernel_evaluations");
        e.weightSums = st->GetCounter("weight_sums");
        e.gradientEvaluations = st->GetCounter("gradient_evaluations");
        e.samples = st->GetCounter("samples");
        e.contourSamples = st->GetCounter("contour_samples");
        RecordSPH(opt, r, e, rows);
        return r;
      };
      for (const Group& g : groups)
      {
        const bool any = std::any_of(g.methods.begin(), g.methods.end(),
                           [&](const Ours& o) { return Selected(opt, o.method); }) ||
          (g.key == "normalized" &&
            std::any_of(theirs.begin(), theirs.end(),
              [&](const Theirs& t) { return Selected(opt, t.method); }));
        if (!any)
        {
          continue;
        }
        std::string setting = "step=0.25;sps=64;ert=1";
        if (g.key != "normalized")
        {
          setting = g.key + ";" + setting;
        }
        if (opt.references)
        {
          Ours ref = ours("reference", setting, g.reference, "");
          ref.method.repeat = 1;
          references[g.key] = measureOurs(ref, "").image;
        }
        for (const Ours& o : g.methods)
        {
          if (Selected(opt, o.method))
          {
            measureOurs(o, o.reference);
          }
        }
        if (g.key == "normalized")
        {
          for (const Theirs& t : theirs)
          {
            if (!Selected(opt, t.method))
            {
              continue;
            }
            Result r = Measure(opt, t.method, camera);
            r.row.suite = "sph";
            r.row.dataset = dataset;
            r.row.items = n;
            if (references["normalized"])
            {
              Compare(references["normalized"], r.image, r.row.rmse, r.row.maxErr);
            }
            Extra e;
            e.resampleMs = t.grid->ms;
            e.firstFrameMs = t.log->frameMs.empty() ? -1 : t.log->frameMs[0];
            e.frameMs = e.resampleMs + e.firstFrameMs;
            const int* dims = t.grid->image->GetDimensions();
            std::cout << "  grid " << dims[0] << "x" << dims[1] << "x" << dims[2] << ", spacing "
                      << t.grid->spacing << " (h = " << d.h << ")\n";
            RecordSPH(opt, r, e, rows);
          }
        }
      }
    }
  }
  const std::vector<Row> voxelRows = RunSPHVoxel(opt, files);
  rows.insert(rows.end(), voxelRows.begin(), voxelRows.end());
  return rows;
}

} // namespace bench
