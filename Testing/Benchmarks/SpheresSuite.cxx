// The spheres suite: vtkCGTSphereMapper with the coherent grid (cgt) and with Embree's BVH
// (embree, the reference image), against vtkPointGaussianMapper with a sphere imposter
// (vtk-point-gaussian); the lambda, packet and SIMD sweeps, and the accuracy of ambient
// occlusion and soft shadows against their many-ray references.
#include "BenchData.h"
#include "BenchRun.h"
#include "vtkCGTSphereMapper.h"
#include "vtkRayMapperStatistics.h"

#include "vtkActor.h"
#include "vtkCamera.h"
#include "vtkDataArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPointGaussianMapper.h"
#include "vtkPolyData.h"
#include "vtkProperty.h"
#include "vtkRenderer.h"
#include "vtkSmartPointer.h"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

namespace bench
{

namespace
{
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

/// The sphere datasets: uniformly dense ones, the LAMMPS melt (1,000,188 atoms), a LAMMPS
/// crack (a flat slab), 2LYZ and two LIGGGHTS packings (radii 1 : 2.5 and 1 : 10), and
/// clustered ones, an NFW dark-matter halo (galpy) and a Plummer star cluster, each of
/// 1,000,000 particles whose density spans orders of magnitude from the core to the outskirts.
std::vector<std::string> DefaultSphereData(const Options& opt)
{
  std::vector<std::string> files;
  for (const auto& [name, script] : { std::pair{ "lammps_melt_1M.vtk", "lammps_melt.sh" },
         std::pair{ "lammps_crack.vtk", "lammps_crack.sh" },
         std::pair{ "liggghts_packing.vtk", "liggghts_packing.sh" },
         std::pair{ "liggghts_packing_wide.vtk", "liggghts_packing_wide.sh" },
         std::pair{ "galpy_halo_1M.vtk", "galpy_halo.sh" },
         std::pair{ "plummer_1M.vtk", "plummer_sphere.sh" } })
  {
    const std::string path = Generated(opt, name, script);
    if (!path.empty())
    {
      files.push_back(path);
    }
  }
  files.insert(files.begin() + std::min<std::size_t>(files.size(), 1),
    std::string(RAYMAPPERS_SOURCE_DIR) + "/Data/2LYZ.pdb");
  return files;
}

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
    // The radius as the representation chooses it (a radius array, else half the typical
    // spacing: touching spheres), or --radius.
    const ParticleSize size = ChooseSize(cloud, vtkRayMapperParticleSizes::Role::Radius, false,
      SphereRadiusPerSpacing, opt.radius);
    const bool radii = !size.array.empty();
    const std::string& radiusName = size.array;
    const double radiusFactor = size.scale;
    const double constantRadius = size.constant;
    vtkDataArray* colors = nullptr;
    if (!ChooseValueArray(cloud, opt.array, file, false, colors))
    {
      continue;
    }
    double range[2] = { 0, 1 };
    if (colors)
    {
      colors->GetRange(range);
    }
    std::cout << bench::BaseName(file) << ": " << n << " points, radius " << size.how
              << ", color " << (colors && colors->GetName() ? colors->GetName() : "none") << "\n";

    // One view for all methods: the data seen from a corner, filling the image (--zoom: the
    // camera that many times closer, looking at the centre or at --focus).
    auto view = [&](vtkCamera* cam)
    {
      double b[6];
      cloud->GetBounds(b);
      double c[3] = { 0.5 * (b[0] + b[1]), 0.5 * (b[2] + b[3]), 0.5 * (b[4] + b[5]) };
      std::copy(opt.focus.begin(), opt.focus.end(), c);
      const double diag = std::sqrt((b[1] - b[0]) * (b[1] - b[0]) + (b[3] - b[2]) * (b[3] - b[2]) +
                                    (b[5] - b[4]) * (b[5] - b[4]));
      cam->SetFocalPoint(c);
      const double d = diag / opt.zoom;
      cam->SetPosition(c[0] + 0.8 * d, c[1] + 0.55 * d, c[2] + 1.8 * d);
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
      s << "last build: spheres " << st->GetPhaseTime("spheres") << " ms, grid "
        << st->GetPhaseTime("grid_build") << " ms, bvh " << st->GetPhaseTime("bvh_build")
        << " ms; traced " << (st->GetCounter("accelerator_embree") ? "embree" : "grid")
        << " in " << st->GetPhaseTime("trace") << " ms";
      if (st->GetCounter("grid_crowded_spheres") > 0)
      {
        s << "; grid spheres in leaves > 1024: " << st->GetCounter("grid_crowded_spheres");
      }
      // The work per primary ray: cells visited and ray-sphere tests (the grid counts both).
      if (const double rays = st->GetCounter("rays"))
      {
        s << "; per ray: cells " << st->GetCounter("cells") / rays << ", sphere tests "
          << st->GetCounter("sphere_tests") / rays;
      }
      if (st->GetCounter("grid_bytes") > 0)
      {
        // The grid's own memory (offsets, macrocells) against the particle data it indexes.
        const double particles = cloud->GetActualMemorySize() * 1024.0;
        s << "; grid " << st->GetCounter("grid_bytes") / 1048576.0
          << " MB = " << 100.0 * st->GetCounter("grid_bytes") / particles
          << "% of the particle data (" << particles / 1048576.0 << " MB); simd lanes "
          << st->GetCounter("simd_lanes");
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
    // The mapper's defaults, read from a new one (today the grid, lambda 1 with nested
    // cells, 8 x 8 packets), and the sweeps behind them.
    vtkNew<vtkCGTSphereMapper> defaults;
    const double lambda0 = defaults->GetLambda();
    methods.push_back({ "cgt",
      "default",
      oursWith(defaults->GetAccelerator(), defaults->GetLambda(), defaults->GetPacketSize()),
      oursBuildMs,
      touch,
      buildDetail });
    for (const double lambda : { 0.125, 0.25, 0.5, 2.0 })
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
        "packet=" + std::to_string(packet),
        oursWith(VTK_CGT_ACCELERATOR_GRID, lambda0, packet),
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
        std::string("simd=") + simd.second,
        oursWith(VTK_CGT_ACCELERATOR_GRID, lambda0, 8, 1, 0, 0, simd.first),
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
          oursWith(VTK_CGT_ACCELERATOR_GRID, lambda0, 8, 1, ao),
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
          oursWith(VTK_CGT_ACCELERATOR_GRID, lambda0, 8, 1, 0, side),
          oursBuildMs,
          touch,
          buildDetail });
      }
    }

    vtkSmartPointer<vtkImageData> reference, aoReference, shadowReference;
    for (const Method& m : methods)
    {
      const bool isReference =
        m.setting == "bvh=medium" || m.setting == "ao=256" || m.setting == "shadows=16x16";
      if (!Selected(opt, m) && !(isReference && opt.references))
      {
        continue; // (the references run unless --no-reference)
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
      Record(opt, r, rows);
    }
  }
  return rows;
}

} // namespace bench
