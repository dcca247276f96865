// What the two halves of the sph suite share: SPHSuite.cxx (vtkSPHVolumeMapper against
// resampling + volume ray casting) and SPHVoxelSuite.cxx (vtkSPHFluidMapper and
// vtkSPHVoxelizer against resampling + contouring): the PySPH data, the views, the resample
// onto an image grid and the CSV's extra columns.
#ifndef RayMappers_SPHSuite_h
#define RayMappers_SPHSuite_h

#include "BenchData.h"
#include "BenchRun.h"

#include "vtkSmartPointer.h"

#include <functional>
#include <string>
#include <vector>

class vtkCamera;
class vtkImageData;
class vtkPolyData;

namespace bench
{
namespace sph
{

struct Dataset
{
  std::string file, name;
  vtkSmartPointer<vtkPolyData> particles;
  ParticleSize smoothing;    // the smoothing length h: an array, or a constant
  double h = 0;              // the largest smoothing length (PySPH's h is constant)
  std::string value;         // the sampled quantity (PySPH: vmag)
  std::string mass, density; // V = m / rho (made from the spacing when the file has none)
  double vmax = 1;           // the largest value: the transfer function's top
  double time = -1;          // simulated time from the file's title, -1 if absent
};

/// A legacy file of SPH particles (PySPH's output: h, m, rho, vmag) and the arrays the suite
/// uses, chosen as raymappers-bench.cxx describes (--array, --h); no particles and a message
/// when it cannot be read or lacks the --array.
Dataset Load(const std::string& file, const Options& opt);

/// The default data: the shipped coarse frame and the fine time step closest to t = 0.3 s.
std::vector<std::string> DefaultFiles(const Options& opt);

/// The camera of a view of the dam break: "outside" (the whole fluid from the side and
/// above) or "surface" (close to the free surface of the collapsing column).
std::function<void(vtkCamera*)> View(const Dataset& d, const std::string& view);

/// An image grid resampled from the particles by vtkSPHInterpolator.
struct Resampled
{
  vtkSmartPointer<vtkImageData> image; // scalars: the value; also "Shepard Summation"
  double ms = 0;
  double spacing = 0;
};

/// vtkSPHInterpolator (Wendland C2 with the largest h, V = m / rho, Shepard normalized) onto a
/// grid of `res` points along the longest side of the particles' bounds grown by the support
/// 2h. The image's scalars are the value, -vmax/2 where no particle reaches; it also keeps the
/// interpolator's "Shepard Summation", sum_j V_j W(x - x_j, h): the fluid's volume fraction.
Resampled Resample(const Dataset& d, int res);

/// A CSV number ("" for a negative value: not measured) and count ("" below 0).
std::string Number(double v);
std::string Count(long long v);

/// The columns that SPHVoxelSuite.cxx adds after SPHSuite.cxx's extra columns, and the
/// empty fields of a row that has none of them.
extern const char* const VoxelCsvColumns;
std::string EmptyVoxelCsv();

/// The extra columns of the volume half that a voxel row also fills (frame_ms ...
/// first_frame_ms); the rest of them stay empty in voxel rows.
struct FrameTimes
{
  double frameMs = -1, resampleMs = -1, firstFrameMs = -1;
};

/// Records a voxel row: the table, its image, and the CSV row with the volume half's extra
/// columns (frame times only) and `voxelCsv` (VoxelCsvColumns' fields).
void RecordVoxelRow(const Options& opt,
  const Result& r,
  const FrameTimes& times,
  const std::string& voxelCsv,
  std::vector<Row>& rows);

/// The fluid half of the suite on `files` (see SPHVoxelSuite.cxx).
std::vector<Row> RunSPHVoxel(const Options& opt, const std::vector<std::string>& files);

} // namespace sph
} // namespace bench

#endif
