// raymappers-bench: renders the same data and camera with our methods and with the
// alternatives a user has today, in one run, and writes one CSV row per (dataset, method,
// setting):
//   suite,dataset,method,setting,width,height,items,build_ms,render_ms,rmse,max_err,mem_mb
// render_ms is the median over --repeat frames of the same view (render + glFinish);
// build_ms the time the method spent building what it reuses between frames; rmse/max_err
// compare with the suite's reference image (0..1 per channel), empty for the reference
// itself; mem_mb the growth of the process's resident memory over the method's first frame.
// The sph suite's CSV has more columns after these (frame_ms, resample_ms, phases and
// counters: see SPHSuite.cxx; then the fluid rows' stages, counters and surface errors: see
// SPHVoxelSuite.cxx).
//
// usage: raymappers-bench SUITE [--data FILE ...] [--size WxH] [--repeat N] [--csv FILE]
//                               [--images DIR] [--generated DIR] [--only TEXT ...]
//                               [--threads N] [--array NAME] [--radius R] [--h H]
//                               [--zoom Z] [--focus X,Y,Z] [--no-reference] [--view NAME ...]
// --zoom (spheres) moves the camera Z times closer to the data's centre (a close-up of a
// cluster's core); --focus X,Y,Z looks at that point instead of the centre.
// --no-reference runs only the methods --only picks, without the suite's reference images
// (no rmse): one method per process, for its peak resident memory (the scale scripts).
// --view NAME (repeatable) runs only the suite's views of that name (rbf: far, close; zsweep:
// far, side, close; sph: outside, surface, and the fluid's views).
// --only runs just the methods whose ":method:setting" contains TEXT (and the references);
// a leading ':' anchors TEXT at the method's name, a trailing '$' at the setting's end.
// --threads limits TBB (our mappers' parallel work) to N threads, for parallel efficiency.
// Arrays are chosen as the representations choose them, so any particle file runs:
//   size        a point array with a conventional name (vtkRayMapperParticleSizes::
//               FindSizeArrayName: radius, radii, r, diameter x 0.5; h, hsml,
//               smoothing_length), else a constant, a factor times the typical particle
//               spacing (spheres 0.5, rbf 1, sph h 1.2, fluid radius 1); --radius R and
//               --h H set a constant radius and smoothing length instead. Each suite prints
//               which it took.
//   value       (the spheres' colour, the rbf weight, the sph quantity, the zsweep scalars)
//               the point array --array NAME; else (sph) a speed: vmag, speed,
//               velocity_magnitude, or the magnitude of a 3-component v, vel or velocity;
//               else (rbf) a weight of 1, or one that follows the density with an h array;
//               else the active point scalars (zsweep: Density, Temp, RTData of the bundled
//               data), else type, atom_type, Temp, temperature, rho, density, else the first
//               1-component array. A legacy file's first SCALARS section is its active
//               scalars whatever it holds (PySPH's is rho): that is why sph looks for a speed
//               first. A missing --array names the file, the array and the arrays present,
//               and the file is skipped.
//   mass, density  (sph) m or mass and rho or density, ignoring case; without them the
//               particle volume is the typical spacing cubed, and the suite says so.
// build_ms of our mapper is the median over --repeat rebuilds after the data is marked
// modified (a new time step), and the breakdown is printed.
#include "BenchRun.h"

#include "vtksys/SystemTools.hxx"

#include <tbb/global_control.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>

using namespace bench;

namespace bench
{
// The sph suite (SPHSuite.cxx) and the columns its CSV has after the common ones.
std::vector<Row> RunSPH(const Options& opt);
extern const char* const SPHCsvExtraColumns;
}

namespace
{
int Usage()
{
  std::cerr << "usage: raymappers-bench SUITE [--data FILE ...] [--size WxH] [--repeat N] "
               "[--csv FILE] [--images DIR] [--generated DIR] [--only METHOD:SETTING ...] "
               "[--threads N] [--array NAME] [--radius R] [--h H] [--zoom Z] [--focus X,Y,Z] [--no-reference] [--view NAME]\n"
               "--array: the point array to colour or sample by (default: chosen by name)\n"
               "--radius, --h: a constant particle radius, SPH smoothing length (default: "
               "the data's size array, else a multiple of the particle spacing)\n"
               "--zoom: (spheres) the camera Z times closer to the data's centre\n"
               "suites: spheres, rbf, zsweep, sph\n";
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
    else if (a == "--view")
    {
      opt.views.push_back(next());
    }
    else if (a == "--generated")
    {
      opt.generated = next();
    }
    else if (a == "--array")
    {
      opt.array = next();
    }
    else if (a == "--radius" || a == "--h")
    {
      const double value = std::atof(next().c_str());
      if (!(value > 0))
      {
        std::cerr << a << " takes a positive length\n";
        return 2;
      }
      (a == "--radius" ? opt.radius : opt.h) = value;
    }
    else if (a == "--no-reference")
    {
      opt.references = false;
    }
    else if (a == "--focus")
    {
      std::istringstream in(next());
      opt.focus.assign(3, 0.0);
      char comma = ',';
      if (!(in >> opt.focus[0] >> comma >> opt.focus[1] >> comma >> opt.focus[2]))
      {
        std::cerr << "--focus takes X,Y,Z\n";
        return 2;
      }
    }
    else if (a == "--zoom")
    {
      opt.zoom = std::atof(next().c_str());
      if (!(opt.zoom >= 1))
      {
        std::cerr << "--zoom takes a factor of at least 1\n";
        return 2;
      }
    }
    else if (a == "--threads")
    {
      opt.threads = std::max(1, std::atoi(next().c_str()));
    }
    else
    {
      std::cerr << "unknown option " << a << "\n";
      return Usage();
    }
  }

  if (!opt.csv.empty())
  {
    std::ofstream out(opt.csv); // the header; each suite appends its rows as it measures
    out << CsvHeader << (opt.suite == "sph" ? std::string(",") + SPHCsvExtraColumns : "")
        << "\n";
  }
  std::unique_ptr<tbb::global_control> threads;
  if (opt.threads > 0)
  {
    threads = std::make_unique<tbb::global_control>(
      tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(opt.threads));
  }
  std::vector<Row> rows;
  if (opt.suite == "spheres")
  {
    rows = RunSpheres(opt);
  }
  else if (opt.suite == "rbf")
  {
    rows = RunRBF(opt);
  }
  else if (opt.suite == "zsweep")
  {
    rows = RunZSweep(opt);
  }
  else if (opt.suite == "sph")
  {
    rows = RunSPH(opt);
  }
  else
  {
    return Usage();
  }

  PrintTable(rows);
  if (!opt.csv.empty())
  {
    std::cout << "wrote " << opt.csv << "\n";
  }
  return rows.empty() ? 1 : 0;
}
