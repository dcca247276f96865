// raymappers-bench: renders the same data and camera with our methods and with the
// alternatives a user has today, in one run, and writes one CSV row per (dataset, method,
// setting):
//   suite,dataset,method,setting,width,height,items,build_ms,render_ms,rmse,max_err,mem_mb
// render_ms is the median over --repeat frames of the same view (render + glFinish);
// build_ms the time the method spent building what it reuses between frames; rmse/max_err
// compare with the suite's reference image (0..1 per channel), empty for the reference
// itself; mem_mb the growth of the process's resident memory over the method's first frame.
//
// usage: raymappers-bench SUITE [--data FILE ...] [--size WxH] [--repeat N] [--csv FILE]
//                               [--images DIR] [--generated DIR] [--only TEXT ...]
// --only runs just the methods whose "method:setting" contains TEXT (and the references).
// build_ms of our mapper is the median over --repeat rebuilds after the data is marked
// modified (a new time step), and the breakdown is printed.
#include "BenchData.h"
#include "vtkCGTSphereMapper.h"
#include "vtkRayMapperStatistics.h"

#include "vtkActor.h"
#include "vtkCamera.h"
#include "vtkDataArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPNGWriter.h"
#include "vtkPointData.h"
#include "vtkPointGaussianMapper.h"
#include "vtkPolyData.h"
#include "vtkProperty.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkSmartPointer.h"
#include "vtkUnsignedCharArray.h"
#include "vtkWindowToImageFilter.h"
#include "vtksys/SystemTools.hxx"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <iostream>
#include <sstream>
#include <string>
#include <unistd.h>
#include <vector>

namespace
{

struct Options
{
  std::string suite;
  std::vector<std::string> data;
  int width = 1024;
  int height = 1024;
  int repeat = 5;
  std::string csv;
  std::string images;
  std::string generated = RAYMAPPERS_GENERATED_DIR;
  std::vector<std::string> only; // run only methods whose "method:setting" contains one
};

struct Row
{
  std::string suite, dataset, method, setting;
  int width = 0, height = 0;
  long long items = 0;
  double buildMs = 0, renderMs = 0;
  double rmse = -1, maxErr = -1; // < 0: no reference
  double memMb = 0;
};

double ResidentMb()
{
  std::ifstream statm("/proc/self/statm");
  long pages = 0, resident = 0;
  statm >> pages >> resident;
  return resident * static_cast<double>(sysconf(_SC_PAGESIZE)) / (1024.0 * 1024.0);
}

double Median(std::vector<double> v)
{
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n == 0 ? 0.0 : (n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]));
}

double Now()
{
  return std::chrono::duration<double, std::milli>(
    std::chrono::steady_clock::now().time_since_epoch())
    .count();
}

/// What one method renders into a window: it adds its props to the renderer.
struct Method
{
  std::string name;
  std::string setting;
  std::function<void(vtkRenderer*)> setup;
  std::function<double()> buildMs;          // read after a frame; nullptr: first frame - median
  std::function<void()> touch;              // marks the data modified, as a new time step does
  std::function<std::string()> buildDetail; // what the build time is made of
};

struct Result
{
  Row row;
  vtkSmartPointer<vtkImageData> image;
};

Result Measure(const Options& opt, const Method& m, const std::function<void(vtkCamera*)>& view)
{
  vtkNew<vtkRenderer> ren;
  ren->SetBackground(1, 1, 1);
  vtkNew<vtkRenderWindow> win;
  win->SetOffScreenRendering(1);
  win->SetSize(opt.width, opt.height);
  win->AddRenderer(ren);
  m.setup(ren);
  view(ren->GetActiveCamera());
  ren->ResetCameraClippingRange();

  const double mem0 = ResidentMb();
  double t0 = Now();
  win->Render();
  win->WaitForCompletion();
  const double first = Now() - t0;
  const double mem1 = ResidentMb();
  double build = m.buildMs ? m.buildMs() : -1.0;
  std::vector<double> times;
  for (int i = 0; i < opt.repeat; ++i)
  {
    t0 = Now();
    win->Render();
    win->WaitForCompletion();
    times.push_back(Now() - t0);
  }
  // The build of a time step: the data marked modified and rendered again, --repeat times.
  if (m.buildMs && m.touch)
  {
    std::vector<double> builds;
    for (int i = 0; i < opt.repeat; ++i)
    {
      m.touch();
      win->Render();
      win->WaitForCompletion();
      builds.push_back(m.buildMs());
    }
    build = Median(builds);
  }
  if (m.buildDetail)
  {
    std::cout << "  " << m.name << " " << m.setting << ": " << m.buildDetail() << std::endl;
  }
  Result r;
  r.row.method = m.name;
  r.row.setting = m.setting;
  r.row.width = opt.width;
  r.row.height = opt.height;
  r.row.renderMs = Median(times);
  r.row.buildMs = build >= 0 ? build : std::max(0.0, first - r.row.renderMs);
  r.row.memMb = std::max(0.0, mem1 - mem0);
  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(win);
  grab->ReadFrontBufferOff();
  grab->SetInputBufferTypeToRGB();
  grab->Update();
  r.image = vtkSmartPointer<vtkImageData>::New();
  r.image->DeepCopy(grab->GetOutput());
  return r;
}

/// RMSE and maximum absolute difference of two RGB images, channels in 0..1.
void Compare(vtkImageData* a, vtkImageData* b, double& rmse, double& maxErr)
{
  auto* pa = static_cast<unsigned char*>(a->GetScalarPointer());
  auto* pb = static_cast<unsigned char*>(b->GetScalarPointer());
  const long n = static_cast<long>(a->GetNumberOfPoints()) * 3;
  double sum = 0, mx = 0;
  for (long i = 0; i < n; ++i)
  {
    const double d = (static_cast<int>(pa[i]) - static_cast<int>(pb[i])) / 255.0;
    sum += d * d;
    mx = std::max(mx, std::fabs(d));
  }
  rmse = std::sqrt(sum / static_cast<double>(n));
  maxErr = mx;
}

void WritePng(vtkImageData* image, const std::string& path)
{
  vtkNew<vtkPNGWriter> w;
  w->SetInputData(image);
  w->SetFileName(path.c_str());
  w->Write();
}

// A sphere imposter for vtkPointGaussianMapper (what ParaView's Point Gaussian "Sphere"
// preset gives users): discard outside the unit disc and shade with the normal of a
// sphere seen head-on, n = (x, y, sqrt(1 - x^2 - y^2)), lit from the viewer. Its depth is
// the flat splat's, so intersecting spheres are not resolved.
const char* const SphereImposterShader =
  "//VTK::Color::Impl\n"
  "float d2 = dot(offsetVCVSOutput.xy, offsetVCVSOutput.xy);\n"
  "if (d2 > 1.0) { discard; }\n"
  "float nz = sqrt(1.0 - d2);\n"
  "ambientColor *= 0.1;\n"
  "diffuseColor *= nz;\n";

/// Whether --only selects the method (no --only: all).
bool Selected(const Options& opt, const Method& m)
{
  const std::string key = m.name + ":" + m.setting;
  return opt.only.empty() ||
         std::any_of(opt.only.begin(),
           opt.only.end(),
           [&](const std::string& o) { return key.find(o) != std::string::npos; });
}

std::vector<std::string> DefaultSphereData(const Options& opt)
{
  const std::string melt = opt.generated + "/lammps_melt_1M.vtk";
  if (!vtksys::SystemTools::FileExists(melt, true))
  {
    vtksys::SystemTools::MakeDirectory(opt.generated);
    const std::string cmd = std::string("bash '") + RAYMAPPERS_SOURCE_DIR +
                            "/Data/Generators/lammps_melt.sh' '" + melt + "'";
    std::cout << "generating the LAMMPS melt (1,000,188 atoms, about a minute): " << cmd
              << std::endl;
    if (std::system(cmd.c_str()) != 0)
    {
      std::cerr << "raymappers-bench: the LAMMPS melt could not be generated; skipping it\n";
      return { std::string(RAYMAPPERS_SOURCE_DIR) + "/Data/2LYZ.pdb" };
    }
  }
  return { std::string(RAYMAPPERS_SOURCE_DIR) + "/Data/2LYZ.pdb", melt };
}

// One empty frame at the benchmark's size, so that the OpenGL driver's one-time allocations
// are not counted in the memory of the first method measured.
void WarmUp(const Options& opt)
{
  vtkNew<vtkRenderer> ren;
  vtkNew<vtkRenderWindow> win;
  win->SetOffScreenRendering(1);
  win->SetSize(opt.width, opt.height);
  win->AddRenderer(ren);
  win->Render();
  win->WaitForCompletion();
}

std::vector<Row> RunSpheres(const Options& opt)
{
  WarmUp(opt);
  std::vector<Row> rows;
  const std::vector<std::string> files = opt.data.empty() ? DefaultSphereData(opt) : opt.data;
  for (const std::string& file : files)
  {
    auto data = bench::ReadAny(file);
    if (!data)
    {
      continue;
    }
    vtkSmartPointer<vtkPolyData> cloud = bench::ToPointCloud(data);
    const long long n = cloud->GetNumberOfPoints();
    if (n == 0)
    {
      std::cerr << "raymappers-bench: " << file << " has no points; skipped\n";
      continue;
    }
    std::string radiusName;
    double radiusFactor = 1.0;
    vtkDataArray* radii = bench::FindRadiusArray(cloud, radiusName, radiusFactor);
    const double constantRadius = bench::DefaultRadius(cloud);
    vtkDataArray* colors = bench::FindColorArray(cloud);
    double range[2] = { 0, 1 };
    if (colors)
    {
      colors->GetRange(range);
    }
    std::cout << bench::BaseName(file) << ": " << n << " points, radius "
              << (radii ? "array '" + radiusName + "'"
                        : "constant " + std::to_string(constantRadius))
              << ", color " << (colors && colors->GetName() ? colors->GetName() : "none") << "\n";

    // One view for all methods: the data seen from a corner, filling the image.
    auto view = [&](vtkCamera* cam)
    {
      double b[6];
      cloud->GetBounds(b);
      const double c[3] = { 0.5 * (b[0] + b[1]), 0.5 * (b[2] + b[3]), 0.5 * (b[4] + b[5]) };
      const double diag = std::sqrt((b[1] - b[0]) * (b[1] - b[0]) + (b[3] - b[2]) * (b[3] - b[2]) +
                                    (b[5] - b[4]) * (b[5] - b[4]));
      cam->SetFocalPoint(c);
      cam->SetPosition(c[0] + 0.8 * diag, c[1] + 0.55 * diag, c[2] + 1.8 * diag);
      cam->SetViewUp(0, 1, 0);
      cam->SetViewAngle(30);
    };

    std::vector<Method> methods;
    vtkSmartPointer<vtkCGTSphereMapper> ours;
    // Our mapper with one accelerator; its build time is the sphere set plus the structure.
    auto oursWith = [&](int accelerator,
                      double lambda,
                      int packet,
                      int quality = 1,
                      int ao = 0,
                      int shadows = 0,
                      int simd = VTK_CGT_SIMD_AUTO)
    {
      return [&, accelerator, lambda, packet, quality, ao, shadows, simd](vtkRenderer* ren)
      {
        ours = vtkSmartPointer<vtkCGTSphereMapper>::New();
        ours->SetSimdInstructions(simd);
        ours->SetEmbreeBuildQuality(quality);
        ours->SetAmbientOcclusionSamples(ao);
        ours->SetShadowRays(shadows);
        ours->SetLambda(lambda);
        ours->SetPacketSize(packet);
        ours->SetAccelerator(accelerator);
        ours->SetInputData(cloud);
        if (radii)
        {
          ours->SetRadiusArrayName(radiusName.c_str());
          ours->SetRadiusScale(radiusFactor);
        }
        else
        {
          ours->SetRadius(constantRadius);
        }
        if (colors)
        {
          ours->SelectColorArray(colors->GetName());
          ours->SetScalarModeToUsePointFieldData();
          ours->SetScalarRange(range);
        }
        vtkNew<vtkActor> actor;
        actor->SetMapper(ours);
        ren->AddActor(actor); // Lambert shading with the renderer's light
      };
    };
    auto oursBuildMs = [&]()
    {
      vtkRayMapperStatistics* st = ours->GetStatistics();
      return st->GetPhaseTime("spheres") + st->GetPhaseTime("grid_build") +
             st->GetPhaseTime("bvh_build");
    };
    auto touch = [&]() { cloud->Modified(); };
    auto buildDetail = [&]()
    {
      vtkRayMapperStatistics* st = ours->GetStatistics();
      std::ostringstream s;
      s << "last build: spheres " << st->GetPhaseTime("spheres") << " ms, "
        << (st->GetPhaseTime("grid_build") > 0 ? "grid " : "bvh ")
        << st->GetPhaseTime("grid_build") + st->GetPhaseTime("bvh_build") << " ms; trace "
        << st->GetPhaseTime("trace") << " ms";
      if (st->GetCounter("grid_bytes") > 0)
      {
        // The grid's own memory (offsets, macrocells) against the particle data it indexes.
        const double particles = cloud->GetActualMemorySize() * 1024.0;
        s << "; grid " << st->GetCounter("grid_bytes") / 1048576.0 << " MB = "
          << 100.0 * st->GetCounter("grid_bytes") / particles << "% of the particle data ("
          << particles / 1048576.0 << " MB); simd lanes " << st->GetCounter("simd_lanes");
      }
      return s.str();
    };
    // Embree at its best: 16-ray coherent packets, and each build quality (low suits a
    // time step, medium or high a static scene).
    methods.push_back({ "embree",
      "bvh=medium",
      oursWith(VTK_CGT_ACCELERATOR_EMBREE, 1.0, 4, 1),
      oursBuildMs,
      touch,
      buildDetail });
    methods.push_back({ "embree",
      "bvh=low",
      oursWith(VTK_CGT_ACCELERATOR_EMBREE, 1.0, 4, 0),
      oursBuildMs,
      touch,
      buildDetail });
    methods.push_back({ "embree",
      "bvh=high",
      oursWith(VTK_CGT_ACCELERATOR_EMBREE, 1.0, 4, 2),
      oursBuildMs,
      touch,
      buildDetail });
    // The defaults (lambda 1, 8 x 8 packets) and the sweep behind them.
    methods.push_back({ "cgt",
      "lambda=1;packet=8",
      oursWith(VTK_CGT_ACCELERATOR_GRID, 1.0, 8),
      oursBuildMs,
      touch,
      buildDetail });
    for (const double lambda : { 0.25, 0.5, 2.0, 4.0 })
    {
      std::ostringstream setting;
      setting << "lambda=" << lambda << ";packet=8";
      methods.push_back({ "cgt",
        setting.str(),
        oursWith(VTK_CGT_ACCELERATOR_GRID, lambda, 8),
        oursBuildMs,
        touch,
        buildDetail });
    }
    for (const int packet : { 1, 2, 4, 16 })
    {
      methods.push_back({ "cgt",
        "lambda=1;packet=" + std::to_string(packet),
        oursWith(VTK_CGT_ACCELERATOR_GRID, 1.0, packet),
        oursBuildMs,
        touch,
        buildDetail });
    }
    // The SIMD paths of the ray-sphere tests, side by side (default: the widest the CPU has).
    for (const auto& simd : { std::make_pair(VTK_CGT_SIMD_PORTABLE, "portable"),
           std::make_pair(VTK_CGT_SIMD_AVX2, "avx2"),
           std::make_pair(VTK_CGT_SIMD_AVX512, "avx512") })
    {
      methods.push_back({ "cgt",
        std::string("lambda=1;packet=8;simd=") + simd.second,
        oursWith(VTK_CGT_ACCELERATOR_GRID, 1.0, 8, 1, 0, 0, simd.first),
        oursBuildMs,
        touch,
        buildDetail });
    }
    methods.push_back({ "vtk-point-gaussian",
      "sphere-imposter",
      [&](vtkRenderer* ren)
      {
        vtkNew<vtkPointGaussianMapper> pg;
        pg->SetInputData(cloud);
        if (radii)
        {
          pg->SetScaleArray(radiusName.c_str());
          pg->SetScaleFactor(radiusFactor);
        }
        else
        {
          pg->SetScaleFactor(constantRadius);
        }
        pg->SetEmissive(0);
        pg->SetSplatShaderCode(SphereImposterShader);
        if (colors)
        {
          pg->SelectColorArray(colors->GetName());
          pg->SetScalarModeToUsePointFieldData();
          pg->SetScalarRange(range);
        }
        vtkNew<vtkActor> actor;
        actor->SetMapper(pg);
        ren->AddActor(actor);
      },
      nullptr,
      nullptr,
      nullptr });

    // Accuracy against time of ambient occlusion: 4 to 64 rays per hit against 256 (the
    // reference of these rows), on data small enough for 256 secondary rays per pixel.
    const bool aoSweep = n <= 100000;
    if (aoSweep)
    {
      for (const int ao : { 256, 4, 16, 64 })
      {
        methods.push_back({ "cgt",
          "ao=" + std::to_string(ao),
          oursWith(VTK_CGT_ACCELERATOR_GRID, 1.0, 8, 1, ao),
          oursBuildMs,
          touch,
          buildDetail });
      }
    }

    // Soft shadows: 1x1 to 8x8 shadow rays per hit against 16x16 (the automatic light).
    if (aoSweep)
    {
      for (const int side : { 16, 1, 2, 4, 8 })
      {
        methods.push_back({ "cgt",
          "shadows=" + std::to_string(side) + "x" + std::to_string(side),
          oursWith(VTK_CGT_ACCELERATOR_GRID, 1.0, 8, 1, 0, side),
          oursBuildMs,
          touch,
          buildDetail });
      }
    }

    vtkSmartPointer<vtkImageData> reference, aoReference, shadowReference;
    for (const Method& m : methods)
    {
      if (!Selected(opt, m) && m.setting != "bvh=medium" && m.setting != "ao=256" &&
          m.setting != "shadows=16x16")
      {
        continue; // (the references always run)
      }
      Result r = Measure(opt, m, view);
      r.row.suite = "spheres";
      r.row.dataset = bench::BaseName(file);
      r.row.items = n;
      if (m.name == "embree" && m.setting == "bvh=medium")
      {
        reference = r.image; // exact ray-sphere hits (tested against brute force)
      }
      else if (m.setting == "ao=256")
      {
        aoReference = r.image;
      }
      else if (m.setting.rfind("ao=", 0) == 0 && aoReference)
      {
        Compare(aoReference, r.image, r.row.rmse, r.row.maxErr);
      }
      else if (m.setting == "shadows=16x16")
      {
        shadowReference = r.image;
      }
      else if (m.setting.rfind("shadows=", 0) == 0 && shadowReference)
      {
        Compare(shadowReference, r.image, r.row.rmse, r.row.maxErr);
      }
      else if (reference)
      {
        Compare(reference, r.image, r.row.rmse, r.row.maxErr);
      }
      if (!opt.images.empty())
      {
        std::string tag = m.name + "-" + m.setting;
        std::replace(tag.begin(), tag.end(), ';', '_');
        std::replace(tag.begin(), tag.end(), '=', '-');
        WritePng(r.image, opt.images + "/spheres-" + r.row.dataset + "-" + tag + ".png");
      }
      rows.push_back(r.row);
    }
  }
  return rows;
}

std::string Csv(const Row& r)
{
  std::ostringstream s;
  s << r.suite << "," << r.dataset << "," << r.method << "," << r.setting << "," << r.width << ","
    << r.height << "," << r.items << "," << r.buildMs << "," << r.renderMs << ",";
  if (r.rmse >= 0)
  {
    s << r.rmse;
  }
  s << ",";
  if (r.maxErr >= 0)
  {
    s << r.maxErr;
  }
  s << "," << r.memMb;
  return s.str();
}

void PrintTable(const std::vector<Row>& rows)
{
  std::printf("\n%-10s %-22s %-20s %-20s %10s %10s %10s %8s %8s %8s\n",
    "suite",
    "dataset",
    "method",
    "setting",
    "items",
    "build_ms",
    "render_ms",
    "rmse",
    "max_err",
    "mem_mb");
  for (const Row& r : rows)
  {
    char rmse[32] = "", maxErr[32] = "";
    if (r.rmse >= 0)
    {
      std::snprintf(rmse, sizeof rmse, "%.4f", r.rmse);
      std::snprintf(maxErr, sizeof maxErr, "%.3f", r.maxErr);
    }
    std::printf("%-10s %-22s %-20s %-20s %10lld %10.1f %10.1f %8s %8s %8.1f\n",
      r.suite.c_str(),
      r.dataset.c_str(),
      r.method.c_str(),
      r.setting.c_str(),
      r.items,
      r.buildMs,
      r.renderMs,
      rmse,
      maxErr,
      r.memMb);
  }
}

int Usage()
{
  std::cerr << "usage: raymappers-bench SUITE [--data FILE ...] [--size WxH] [--repeat N] "
               "[--csv FILE] [--images DIR] [--generated DIR] [--only METHOD:SETTING ...]\n"
               "suites: spheres (rbf, zsweep, sph arrive with their mappers)\n";
  return 2;
}

}

int main(int argc, char* argv[])
{
  if (argc < 2)
  {
    return Usage();
  }
  Options opt;
  opt.suite = argv[1];
  for (int i = 2; i < argc; ++i)
  {
    const std::string a = argv[i];
    auto next = [&]() -> std::string
    {
      if (i + 1 >= argc)
      {
        std::cerr << a << " needs a value\n";
        std::exit(Usage());
      }
      return argv[++i];
    };
    if (a == "--data")
    {
      opt.data.push_back(next());
    }
    else if (a == "--size")
    {
      const std::string s = next();
      if (std::sscanf(s.c_str(), "%dx%d", &opt.width, &opt.height) != 2 || opt.width <= 0 ||
          opt.height <= 0)
      {
        std::cerr << "--size takes WxH, e.g. 1024x1024\n";
        return 2;
      }
    }
    else if (a == "--repeat")
    {
      opt.repeat = std::max(1, std::atoi(next().c_str()));
    }
    else if (a == "--csv")
    {
      opt.csv = next();
    }
    else if (a == "--images")
    {
      opt.images = next();
      vtksys::SystemTools::MakeDirectory(opt.images);
    }
    else if (a == "--only")
    {
      opt.only.push_back(next());
    }
    else if (a == "--generated")
    {
      opt.generated = next();
    }
    else
    {
      std::cerr << "unknown option " << a << "\n";
      return Usage();
    }
  }

  std::vector<Row> rows;
  if (opt.suite == "spheres")
  {
    rows = RunSpheres(opt);
  }
  else if (opt.suite == "rbf" || opt.suite == "zsweep" || opt.suite == "sph")
  {
    std::cerr << "raymappers-bench: the '" << opt.suite
              << "' suite is not available in this version: its mapper has not landed yet.\n";
    return 2;
  }
  else
  {
    return Usage();
  }

  PrintTable(rows);
  if (!opt.csv.empty())
  {
    std::ofstream out(opt.csv);
    out
      << "suite,dataset,method,setting,width,height,items,build_ms,render_ms,rmse,max_err,mem_mb\n";
    for (const Row& r : rows)
    {
      out << Csv(r) << "\n";
    }
    std::cout << "wrote " << opt.csv << "\n";
  }
  return rows.empty() ? 1 : 0;
}
