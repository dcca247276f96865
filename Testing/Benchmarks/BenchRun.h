// The harness of raymappers-bench: options, one CSV row per measured method, the
// measurement of one method in its own window, image comparison and the printed table.
#ifndef RayMappers_BenchRun_h
#define RayMappers_BenchRun_h

#include "vtkSmartPointer.h"

#include <functional>
#include <string>
#include <vector>

class vtkCamera;
class vtkImageData;
class vtkRenderer;

namespace bench
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
  int threads = 0;               // TBB threads; 0: all cores
  std::string array;             // --array: the colour or value array; empty: chosen by name
  double radius = 0;             // --radius: a constant particle radius; 0: from the data
  double h = 0;                  // --h: a constant SPH smoothing length; 0: from the data
  double zoom = 1;               // --zoom: the spheres' camera this many times closer
  std::vector<double> focus;     // --focus X,Y,Z: the spheres' camera looks there (empty: centre)
  bool references = true;        // --no-reference: only the methods --only picks
  std::vector<std::string> views; // --view NAME: only these views (empty: the suite's all)
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

/// What one method renders into a window: it adds its props to the renderer.
struct Method
{
  std::string name;
  std::string setting;
  std::function<void(vtkRenderer*)> setup;
  std::function<double()> buildMs;          // read after a frame; nullptr: first frame - median
  std::function<void()> touch;              // marks the data modified, as a new time step does
  std::function<std::string()> buildDetail; // what the build time is made of
  int repeat = 0;                           // frames to time; 0: --repeat
};

struct Result
{
  Row row;
  vtkSmartPointer<vtkImageData> image;
};

double ResidentMb();
double Median(std::vector<double> v);
double Now();

/// Renders the method in a new off-screen window: the first frame (build), --repeat frames
/// (render_ms, the median), --repeat rebuilds when the method can be touched (build_ms),
/// the memory growth over the first frame, and the final image; then `inspect`, if given,
/// looks at the renderer before its window closes (e.g. reads the depth buffer).
Result Measure(const Options& opt,
  const Method& m,
  const std::function<void(vtkCamera*)>& view,
  const std::function<void(vtkRenderer*)>& inspect = nullptr);

/// RMSE and maximum absolute difference of two RGB images, channels in 0..1.
void Compare(vtkImageData* a, vtkImageData* b, double& rmse, double& maxErr);
void WritePng(vtkImageData* image, const std::string& path);

/// Whether --only selects the method (no --only: all).
bool Selected(const Options& opt, const Method& m);
// Whether the suite's view runs: --view names it, or no --view was given.
bool ViewSelected(const Options& opt, const std::string& view);

/// The file `name` in the --generated folder, made by Data/Generators/`script` when it is
/// not there yet (a real simulator run, cached); empty when the generation failed.
std::string Generated(const Options& opt, const std::string& name, const std::string& script);

/// One empty frame at the benchmark's size, so that the OpenGL driver's one-time
/// allocations are not counted in the memory of the first method measured.
void WarmUp(const Options& opt);

std::string Csv(const Row& r);
extern const char* const CsvHeader;
/// Adds the result's row to `rows`, appends it to the --csv file at once (a long run keeps
/// what it measured even if it is stopped) and, with --images, writes its image as
/// <suite>-<dataset>-<method>-<setting>.png.
void Record(const Options& opt, const Result& result, std::vector<Row>& rows);
void PrintTable(const std::vector<Row>& rows);

/// The suites.
std::vector<Row> RunSpheres(const Options& opt);
std::vector<Row> RunRBF(const Options& opt);
std::vector<Row> RunZSweep(const Options& opt);

} // namespace bench

#endif
