// The rbf suite: vtkRBFVolumeMapper's coherent method (rbf) against its direct method on the
// same BVH (direct-rbf) and against what a VTK user does today, resampling the particles onto
// an image grid with vtkPointInterpolator and a Gaussian kernel, then ray casting it with
// vtkFixedPointVolumeRayCastMapper (resample-volume, at several grid sizes). The reference
// image of the error columns is a converged RBF image (dt / 4, sigma 4, no early
// termination). Sweeps of dt, sigma, the termination threshold, leaf size, packet size and
// samples per pass show what accuracy costs. Every dataset is seen from far and close.
#include "BenchData.h"
#include "BenchRun.h"
#include "vtkRBFVolumeMapper.h"
#include "vtkRayMapperStatistics.h"

#include "vtkCamera.h"
#include "vtkColorTransferFunction.h"
#include "vtkDataArray.h"
#include "vtkFixedPointVolumeRayCastMapper.h"
#include "vtkFloatArray.h"
#include "vtkGaussianKernel.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointData.h"
#include "vtkPointInterpolator.h"
#include "vtkPolyData.h"
#include "vtkRenderer.h"
#include "vtkSmartPointer.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

namespace bench
{

namespace
{
struct Dataset
{
  std::string file;
  vtkSmartPointer<vtkPolyData> cloud;
  std::string radiusArray; // empty: constant radius
  double radiusFactor = 1.0;
  double radius = 1.0;    // mean radius (the constant one without an array)
  std::string fieldArray; // empty: one field
  std::string valueArray; // empty: every particle 1
  double peak = 1.5;      // about the largest field value, for the transfer function
};

// A volume property for a field whose values reach about `peak`: colour from blue through
// white to orange, opacity rising from 10 % of the peak, per `unit` (the mean radius).
vtkSmartPointer<vtkVolumeProperty> MakeProperty(double peak, double unit, int fields)
{
  auto property = vtkSmartPointer<vtkVolumeProperty>::New();
  property->SetIndependentComponents(1);
  for (int m = 0; m < fields; ++m)
  {
    vtkNew<vtkColorTransferFunction> color;
    vtkNew<vtkPiecewiseFunction> opacity;
    if (m == 0)
    {
      color->AddRGBPoint(0.0, 0.23, 0.30, 0.75);
      color->AddRGBPoint(0.5 * peak, 0.87, 0.87, 0.87);
      color->AddRGBPoint(peak, 0.71, 0.02, 0.15);
    }
    else
    {
      color->AddRGBPoint(0.0, 0.1, 0.6, 0.2);
      color->AddRGBPoint(peak, 0.95, 0.85, 0.1);
    }
    opacity->AddPoint(0.0, 0.0);
    opacity->AddPoint(0.1 * peak, 0.0);
    opacity->AddPoint(peak, 0.35);
    property->SetColor(m, color);
    property->SetScalarOpacity(m, opacity);
    property->SetScalarOpacityUnitDistance(m, unit);
  }
  return property;
}

// The radius as the RBF representation chooses it (a radius array, else an h array; else
// the typical spacing: a Gaussian as wide as the spacing), or --radius; d.radius the mean.
void ChooseRadius(Dataset& d, const Options& opt)
{
  const ParticleSize size = ChooseSize(d.cloud, vtkRayMapperParticleSizes::Role::Radius, true,
    RBFRadiusPerSpacing, opt.radius);
  std::cout << BaseName(d.file) << ": radius " << size.how << "\n";
  d.radiusArray = size.array;
  d.radiusFactor = size.scale;
  d.radius = size.constant;
  vtkDataArray* radii = d.cloud->GetPointData()->GetArray(d.radiusArray.c_str());
  if (!d.radiusArray.empty() && radii)
  {
    double sum = 0;
    for (vtkIdType i = 0; i < radii->GetNumberOfTuples(); ++i)
    {
      sum += radii->GetComponent(i, 0);
    }
    d.radius = d.radiusFactor * sum / std::max<vtkIdType>(1, radii->GetNumberOfTuples());
  }
}

// Without --array: SPH-like data (a smoothing length h per particle, about 32 neighbours
// within h) get the weight k = (h_median / h)^3, which follows the density (1 for a median
// particle, far more in the core; k = 1 and a constant neighbour count give a nearly flat
// field); other data k = 1.
void AddDensityWeight(Dataset& d)
{
  double scale = 1.0;
  const char* name = vtkRayMapperParticleSizes::FindSizeArrayName(
    d.cloud, vtkRayMapperParticleSizes::Role::SmoothingLength, false, scale);
  vtkDataArray* h = name ? d.cloud->GetPointData()->GetArray(name) : nullptr;
  if (!h)
  {
    return;
  }
  std::vector<double> sorted(static_cast<std::size_t>(h->GetNumberOfTuples()));
  for (vtkIdType i = 0; i < h->GetNumberOfTuples(); ++i)
  {
    sorted[static_cast<std::size_t>(i)] = h->GetComponent(i, 0);
  }
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
  const double median = sorted[sorted.size() / 2];
  vtkNew<vtkFloatArray> k;
  k->SetName("density_weight");
  k->SetNumberOfTuples(h->GetNumberOfTuples());
  for (vtkIdType i = 0; i < h->GetNumberOfTuples(); ++i)
  {
    k->SetValue(i, static_cast<float>(std::pow(median / h->GetComponent(i, 0), 3.0)));
  }
  d.cloud->GetPointData()->AddArray(k);
  d.valueArray = "density_weight";
  d.peak = 40.0;
}

// The file's particles, radius and weights; no cloud when it cannot be read or lacks the
// --array (the weight of each particle then).
Dataset Prepare(const std::string& file, const Options& opt)
{
  Dataset d;
  d.file = file;
  auto data = ReadAny(file);
  if (!data)
  {
    return d;
  }
  d.cloud = ToPointCloud(data);
  ChooseRadius(d, opt);
  if (!opt.array.empty())
  {
    vtkDataArray* value = nullptr;
    if (!ChooseValueArray(d.cloud, opt.array, file, false, value))
    {
      d.cloud = nullptr;
      return d;
    }
    d.valueArray = opt.array;
    double range[2];
    value->GetRange(range, 0);
    d.peak = range[1] > 0 ? 1.5 * range[1] : 1.5; // k = 1 reaches about 1.5 (the default)
  }
  else
  {
    AddDensityWeight(d);
  }
  // PDB: two fields, carbon (atomic number 6 in vtkPDBReader's atom_type) and the rest.
  if (vtkDataArray* types = d.cloud->GetPointData()->GetArray("atom_type"))
  {
    vtkNew<vtkFloatArray> carbon;
    carbon->SetName("carbon_or_not");
    carbon->SetNumberOfTuples(types->GetNumberOfTuples());
    for (vtkIdType i = 0; i < types->GetNumberOfTuples(); ++i)
    {
      carbon->SetValue(i, types->GetComponent(i, 0) == 6 ? 0.f : 1.f);
    }
    d.cloud->GetPointData()->AddArray(carbon);
    d.fieldArray = "carbon_or_not";
  }
  return d;
}
}

std::vector<Row> RunRBF(const Options& opt)
{
  WarmUp(opt);
  std::vector<std::string> files = opt.data;
  if (files.empty())
  {
    for (const auto& [name, script] : { std::pair{ "lammps_melt_1M.vtk", "lammps_melt.sh" },
           std::pair{ "lammps_crack.vtk", "lammps_crack.sh" },
           std::pair{ "galpy_halo_1M.vtk", "galpy_halo.sh" } })
    {
      const std::string path = Generated(opt, name, script);
      if (!path.empty())
      {
        files.push_back(path);
      }
    }
    files.insert(files.begin(), std::string(RAYMAPPERS_SOURCE_DIR) + "/Data/2LYZ.pdb");
  }
  std::vector<Row> rows;
  for (const std::string& file : files)
  {
    const Dataset d = Prepare(file, opt);
    if (!d.cloud || d.cloud->GetNumberOfPoints() == 0)
    {
      std::cerr << "raymappers-bench: " << file << " has no points; skipped\n";
      continue;
    }
    const long long n = d.cloud->GetNumberOfPoints();
    const int fields = d.fieldArray.empty() ? 1 : 2;
    // The field peaks near kappa times the particles overlapping a point: about 1.5 for
    // these data at sigma 2.
    const auto property = MakeProperty(d.peak, d.radius, fields);
    const double dt = 0.5 * d.radius;
    std::cout << BaseName(file) << ": " << n << " particles, mean radius " << d.radius
              << (d.radiusArray.empty() ? " (constant)" : " (array '" + d.radiusArray + "')")
              << ", fields " << fields << ", dt " << dt << "\n";

    for (const std::string view : { "far", "close" })
    {
      if (!ViewSelected(opt, view))
      {
        continue;
      }
      auto camera = [&](vtkCamera* cam)
      {
        double b[6];
        d.cloud->GetBounds(b);
        const double c[3] = { 0.5 * (b[0] + b[1]), 0.5 * (b[2] + b[3]), 0.5 * (b[4] + b[5]) };
        const double diag =
          std::sqrt((b[1] - b[0]) * (b[1] - b[0]) + (b[3] - b[2]) * (b[3] - b[2]) +
                    (b[5] - b[4]) * (b[5] - b[4]));
        cam->SetFocalPoint(c);
        cam->SetPosition(c[0] + 0.8 * diag, c[1] + 0.55 * diag, c[2] + 1.8 * diag);
        cam->SetViewUp(0, 1, 0);
        cam->SetViewAngle(30);
        if (view == "close")
        {
          cam->Zoom(4.0);
        }
      };

      vtkSmartPointer<vtkRBFVolumeMapper> ours;
      auto rbf = [&](int method,
                   double step,
                   double sigma,
                   double termination,
                   int leaf,
                   int packet,
                   int perPass)
      {
        return [&, method, step, sigma, termination, leaf, packet, perPass](vtkRenderer* ren)
        {
          ours = vtkSmartPointer<vtkRBFVolumeMapper>::New();
          ours->SetInputData(d.cloud);
          if (!d.radiusArray.empty())
          {
            ours->SetRadiusArrayName(d.radiusArray.c_str());
            ours->SetRadiusScale(d.radiusFactor);
          }
          else
          {
            ours->SetRadius(d.radius);
          }
          if (!d.fieldArray.empty())
          {
            ours->SetFieldArrayName(d.fieldArray.c_str());
          }
          if (!d.valueArray.empty())
          {
            ours->SetValueArrayName(d.valueArray.c_str());
          }
          ours->SetMethod(method);
          ours->SetSampleDistance(step);
          ours->SetSigma(sigma);
          ours->SetTerminationOpacity(termination);
          ours->SetLeafSize(leaf);
          ours->SetPacketSize(packet);
          ours->SetSamplesPerPass(perPass);
          vtkNew<vtkVolume> volume;
          volume->SetMapper(ours);
          volume->SetProperty(property);
          ren->AddVolume(volume);
        };
      };
      auto buildMs = [&]()
      {
        vtkRayMapperStatistics* st = ours->GetStatistics();
        return st->GetPhaseTime("particles") + st->GetPhaseTime("bvh_build");
      };
      auto detail = [&]()
      {
        vtkRayMapperStatistics* st = ours->GetStatistics();
        const double particles = d.cloud->GetActualMemorySize() * 1024.0;
        std::ostringstream s;
        s << "particles " << st->GetPhaseTime("particles") << " ms, bvh "
          << st->GetPhaseTime("bvh_build") << " ms (" << st->GetCounter("bvh_bytes") / 1048576.0
          << " MB = " << 100.0 * st->GetCounter("bvh_bytes") / particles
          << "% of the particle data), trace " << st->GetPhaseTime("trace") << " ms, samples "
          << st->GetCounter("samples") << ", culled packets " << st->GetCounter("culled_packets")
          << " of " << st->GetCounter("packets") << ", staggered blocks "
          << st->GetCounter("staggered_blocks") << ", passes " << st->GetCounter("passes")
          << ", node visits " << st->GetCounter("node_visits") << ", deposits "
          << st->GetCounter("deposits")
          << ", opaque depth " << st->GetPhaseTime("opaque_depth") << " ms, draw "
          << st->GetPhaseTime("draw") << " ms";
        return s.str();
      };
      auto ourMethod = [&](const std::string& name,
                         const std::string& setting,
                         int method,
                         double step,
                         double sigma = 2.0,
                         double termination = 0.99,
                         int leaf = 8,
                         int packet = 8,
                         int perPass = 32)
      {
        Method m{ name,
          setting,
          rbf(method, step, sigma, termination, leaf, packet, perPass),
          buildMs,
          nullptr,
          detail };
        return m;
      };

      std::vector<Method> methods;
      methods.push_back(ourMethod(
        "rbf", "reference;dt/4;sigma=4;term=1", VTK_RBF_METHOD_COHERENT, dt / 4, 4.0, 1.0));
      methods.back().repeat = 1;
      methods.push_back(ourMethod("rbf", "default", VTK_RBF_METHOD_COHERENT, dt));
      methods.push_back(ourMethod("direct-rbf", "default", VTK_RBF_METHOD_DIRECT, dt));
      methods.back().repeat = 1;
      // The sweeps behind the defaults, on the far view of the data up to 400,000
      // particles (the close view and the million-particle data repeat the main comparison).
      if (view == "far" && n <= 400000)
      {
        for (const double f : { 2.0, 0.5 })
        {
          methods.push_back(
            ourMethod("rbf", "dt=" + std::to_string(f).substr(0, 3) + "x", 0, dt * f));
        }
        for (const double sigma : { 1.5, 3.0, 4.0 })
        {
          methods.push_back(
            ourMethod("rbf", "sigma=" + std::to_string(sigma).substr(0, 3), 0, dt, sigma));
        }
        for (const double term : { 0.9, 0.97, 1.0 })
        {
          methods.push_back(
            ourMethod("rbf", "term=" + std::to_string(term).substr(0, 4), 0, dt, 2.0, term));
        }
        for (const int leaf : { 4, 16 })
        {
          methods.push_back(
            ourMethod("rbf", "leaf=" + std::to_string(leaf), 0, dt, 2.0, 0.99, leaf));
        }
        for (const int packet : { 2, 4 })
        {
          methods.push_back(
            ourMethod("rbf", "packet=" + std::to_string(packet), 0, dt, 2.0, 0.99, 8, packet));
        }
        for (const int perPass : { 16, 64 })
        {
          methods.push_back(
            ourMethod("rbf", "K=" + std::to_string(perPass), 0, dt, 2.0, 0.99, 8, 8, perPass));
        }
      }
      // Resampling onto a grid: VTK's Gaussian kernel exp(-(s d / R)^2) with R = sigma r and
      // sharpness s = sigma / sqrt(2) is exp(-d^2 / 2 r^2), summed (weights not normalized)
      // over the particles within R; one radius for all (the kernel has no per-point
      // radius), the mean one.
      for (const int res :
        view == "far" ? std::vector<int>{ 64, 128, 256 } : std::vector<int>{ 128 })
      {
        auto resampleMs = std::make_shared<double>(0.0);
        methods.push_back({ "resample-volume",
          "grid=" + std::to_string(res),
          [&, res, resampleMs](vtkRenderer* ren)
          {
            const double t0 = Now();
            double b[6];
            d.cloud->GetBounds(b);
            const double grow = 2.0 * d.radius;
            double longest = 0;
            for (int a = 0; a < 3; ++a)
            {
              b[2 * a] -= grow;
              b[2 * a + 1] += grow;
              longest = std::max(longest, b[2 * a + 1] - b[2 * a]);
            }
            const double h = longest / (res - 1);
            vtkNew<vtkImageData> grid;
            grid->SetOrigin(b[0], b[2], b[4]);
            grid->SetSpacing(h, h, h);
            grid->SetDimensions(std::max(2, int(std::ceil((b[1] - b[0]) / h)) + 1),
              std::max(2, int(std::ceil((b[3] - b[2]) / h)) + 1),
              std::max(2, int(std::ceil((b[5] - b[4]) / h)) + 1));
            // One array per field (the particle's value in its own field, 0 in the others),
            // resampled together and ray cast as independent components: what VTK offers
            // for several fields.
            vtkNew<vtkPolyData> source;
            source->SetPoints(d.cloud->GetPoints());
            vtkDataArray* kinds = d.fieldArray.empty()
                                    ? nullptr
                                    : d.cloud->GetPointData()->GetArray(d.fieldArray.c_str());
            vtkDataArray* values = d.valueArray.empty()
                                     ? nullptr
                                     : d.cloud->GetPointData()->GetArray(d.valueArray.c_str());
            for (int m = 0; m < fields; ++m)
            {
              vtkNew<vtkFloatArray> k;
              k->SetName(("k" + std::to_string(m)).c_str());
              k->SetNumberOfTuples(n);
              for (vtkIdType i = 0; i < n; ++i)
              {
                const double value = values ? values->GetComponent(i, 0) : 1.0;
                k->SetValue(i, !kinds || kinds->GetComponent(i, 0) == m ? float(value) : 0.f);
              }
              source->GetPointData()->AddArray(k);
            }
            vtkNew<vtkGaussianKernel> kernel;
            kernel->SetRadius(2.0 * d.radius);
            kernel->SetSharpness(2.0 / std::sqrt(2.0));
            kernel->NormalizeWeightsOff();
            vtkNew<vtkPointInterpolator> interpolator;
            interpolator->SetInputData(grid);
            interpolator->SetSourceData(source);
            interpolator->SetKernel(kernel);
            interpolator->SetNullPointsStrategyToNullValue();
            interpolator->SetNullValue(0.0);
            interpolator->Update();
            auto image = vtkSmartPointer<vtkImageData>::New();
            image->CopyStructure(interpolator->GetOutput());
            vtkNew<vtkFloatArray> scalars;
            scalars->SetName("k");
            scalars->SetNumberOfComponents(fields);
            scalars->SetNumberOfTuples(image->GetNumberOfPoints());
            for (int m = 0; m < fields; ++m)
            {
              scalars->CopyComponent(m,
                interpolator->GetOutput()->GetPointData()->GetArray(
                  ("k" + std::to_string(m)).c_str()),
                0);
            }
            image->GetPointData()->SetScalars(scalars);
            *resampleMs = Now() - t0;
            vtkNew<vtkFixedPointVolumeRayCastMapper> mapper;
            mapper->SetInputData(image);
            mapper->SetSampleDistance(dt);
            mapper->SetAutoAdjustSampleDistances(0);
            vtkNew<vtkVolume> volume;
            volume->SetMapper(mapper);
            volume->SetProperty(property);
            ren->AddVolume(volume);
          },
          [resampleMs]() { return *resampleMs; }, // the resample is its build
          nullptr,
          nullptr });
      }

      vtkSmartPointer<vtkImageData> reference;
      for (const Method& m : methods)
      {
        const bool isReference = m.setting.rfind("reference", 0) == 0;
        if (isReference ? !opt.references : !Selected(opt, m))
        {
          continue;
        }
        Result r = Measure(opt, m, camera);
        r.row.suite = "rbf";
        r.row.dataset = BaseName(file) + "-" + view;
        r.row.items = n;
        if (isReference)
        {
          reference = r.image;
        }
        else if (reference)
        {
          Compare(reference, r.image, r.row.rmse, r.row.maxErr);
        }
        Record(opt, r, rows);
      }
    }
  }
  return rows;
}

} // namespace bench
