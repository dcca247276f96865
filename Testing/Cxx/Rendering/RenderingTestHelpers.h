// Shared pieces of the VTK rendering tests: a small sphere scene with closed-form
// geometry, a warning counter, pixel / depth probes, and the baseline check.
#ifndef RayMappers_RenderingTestHelpers_h
#define RayMappers_RenderingTestHelpers_h

#include "vtkCallbackCommand.h"
#include "vtkCamera.h"
#include "vtkCellArray.h"
#include "vtkCommand.h"
#include "vtkDoubleArray.h"
#include "vtkFloatArray.h"
#include "vtkMatrix4x4.h"
#include "vtkNew.h"
#include "vtkObject.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkSmartPointer.h"
#include "vtkUnsignedCharArray.h"

#include "ImageFiles.h"
#include "vtkRayMapperStatistics.h"

#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <cstdlib>
#include <string>
#include <vector>

namespace rmtest
{

/// Points with a "radius" and a "value" point array.
inline vtkSmartPointer<vtkPolyData> MakeSpheres(const std::vector<std::array<double, 3>>& centers,
  const std::vector<double>& radii)
{
  auto pd = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> pts;
  pts->SetDataTypeToDouble();
  vtkNew<vtkDoubleArray> r;
  r->SetName("radius");
  vtkNew<vtkDoubleArray> v;
  v->SetName("value");
  vtkNew<vtkCellArray> verts;
  for (std::size_t i = 0; i < centers.size(); ++i)
  {
    pts->InsertNextPoint(centers[i].data());
    r->InsertNextValue(radii[i]);
    v->InsertNextValue(static_cast<double>(i));
    verts->InsertNextCell(1);
    verts->InsertCellPoint(static_cast<vtkIdType>(i));
  }
  pd->SetPoints(pts);
  pd->SetVerts(verts);
  pd->GetPointData()->AddArray(r);
  pd->GetPointData()->AddArray(v);
  pd->GetPointData()->SetActiveScalars("value");
  return pd;
}

/// A regular lattice of n^3 spheres in [-1, 1]^3 with radii and values that vary.
inline vtkSmartPointer<vtkPolyData> MakeLattice(int n)
{
  std::vector<std::array<double, 3>> c;
  std::vector<double> r;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
      {
        const double h = 2.0 / (n - 1);
        c.push_back({ -1 + i * h, -1 + j * h, -1 + k * h });
        r.push_back(h * (0.2 + 0.25 * ((i + 2 * j + 3 * k) % 4) / 3.0));
      }
  return MakeSpheres(c, r);
}

/// Counts the warning and error events of the objects it observes.
class EventCounter
{
public:
  EventCounter() { Callback->SetClientData(this), Callback->SetCallback(&EventCounter::On); }
  void Observe(vtkObject* o)
  {
    o->AddObserver(vtkCommand::WarningEvent, Callback);
    o->AddObserver(vtkCommand::ErrorEvent, Callback);
  }
  int Warnings = 0;
  int Errors = 0;
  std::string Last;
  std::vector<std::string> Texts; // every warning and error, in order

private:
  static void On(vtkObject*, unsigned long event, void* self, void* text)
  {
    auto* me = static_cast<EventCounter*>(self);
    (event == vtkCommand::WarningEvent ? me->Warnings : me->Errors)++;
    me->Last = text ? static_cast<const char*>(text) : "";
    me->Texts.push_back(me->Last);
    std::printf("observed %s: %s\n",
      event == vtkCommand::WarningEvent ? "warning" : "error",
      me->Last.c_str());
  }
  vtkNew<vtkCallbackCommand> Callback;
};

/// Window depth VTK would write for a world point, from the renderer's camera.
inline double WindowDepthOf(vtkRenderer* ren, const double p[3])
{
  vtkMatrix4x4* m = ren->GetActiveCamera()->GetCompositeProjectionTransformMatrix(
    ren->GetTiledAspectRatio(), -1, 1);
  double in[4] = { p[0], p[1], p[2], 1 }, out[4];
  m->MultiplyPoint(in, out);
  return 0.5 * out[2] / out[3] + 0.5;
}

/// Display (pixel) coordinates of a world point.
inline void DisplayOf(vtkRenderer* ren, const double p[3], double d[3])
{
  ren->SetWorldPoint(p[0], p[1], p[2], 1.0);
  ren->WorldToDisplay();
  ren->GetDisplayPoint(d);
}

/// Closed-form window depth of the sphere (c, r) along the ray through the centre of pixel
/// (px, py), the ray taken from VTK's own display-to-world; -1 if the ray misses it.
inline double SphereDepthAtPixel(vtkRenderer* ren, int px, int py, const double c[3], double r)
{
  double a[4], b[4];
  ren->SetDisplayPoint(px + 0.5, py + 0.5, 0.0);
  ren->DisplayToWorld();
  ren->GetWorldPoint(a);
  ren->SetDisplayPoint(px + 0.5, py + 0.5, 1.0);
  ren->DisplayToWorld();
  ren->GetWorldPoint(b);
  double o[3], d[3], len = 0;
  for (int i = 0; i < 3; ++i)
  {
    o[i] = a[i] / a[3];
    d[i] = b[i] / b[3] - o[i];
    len += d[i] * d[i];
  }
  len = std::sqrt(len);
  double fd = 0, ff = 0;
  for (int i = 0; i < 3; ++i)
  {
    d[i] /= len;
    fd += (o[i] - c[i]) * d[i];
    ff += (o[i] - c[i]) * (o[i] - c[i]);
  }
  const double disc = fd * fd - (ff - r * r);
  if (disc < 0)
  {
    return -1;
  }
  const double t = -fd - std::sqrt(disc);
  const double p[3] = { o[0] + t * d[0], o[1] + t * d[1], o[2] + t * d[2] };
  return WindowDepthOf(ren, p);
}

/// Window depth in the buffer at the pixel that shows world point p; (px, py) set to it.
inline double BufferDepthAt(vtkRenderer* ren, const double p[3], int& px, int& py)
{
  double d[3];
  DisplayOf(ren, p, d);
  px = static_cast<int>(std::floor(d[0]));
  py = static_cast<int>(std::floor(d[1]));
  return ren->GetRenderWindow()->GetZbufferDataAtPoint(px, py);
}

inline std::vector<unsigned char> ReadRGB(vtkRenderWindow* win)
{
  const int* s = win->GetSize();
  vtkNew<vtkUnsignedCharArray> a;
  win->GetPixelData(0, 0, s[0] - 1, s[1] - 1, 0, a, 0);
  return std::vector<unsigned char>(a->GetPointer(0), a->GetPointer(0) + a->GetNumberOfValues());
}

/// The value after `flag` on the command line ("" when absent).
inline std::string ArgumentAfter(const char* flag, int argc, char* argv[])
{
  for (int i = 0; i + 1 < argc; ++i)
  {
    if (std::string(argv[i]) == flag)
    {
      return argv[i + 1];
    }
  }
  return "";
}

/// The image check of a test: the picture against the baseline given as -V, under its
/// thresholds (Testing/ImageComparison), the picture written to the -T folder.
inline int CompareWithBaseline(const raymappers::test::RGBImage& image, int argc, char* argv[])
{
  const std::string baseline = ArgumentAfter("-V", argc, argv);
  const std::string folder = ArgumentAfter("-T", argc, argv);
  if (baseline.empty() || folder.empty())
  {
    std::printf("an image test needs -V BASELINE and -T FOLDER\n");
    return EXIT_FAILURE;
  }
  return raymappers::test::checkAgainstBaseline(image, baseline, folder) ? EXIT_SUCCESS
                                                                         : EXIT_FAILURE;
}

inline int CompareWithBaseline(vtkRenderWindow* win, int argc, char* argv[])
{
  return CompareWithBaseline(raymappers::test::fromWindow(win), argc, argv);
}

/// The bookkeeping of a bad-input test: checks printed as they run; the warnings and errors
/// an EventCounter saw since the last Warned(); the frame validation of a mapper's last
/// render (vtkRayMapperStatistics::ValidateFrames, switched on here); exact image equality.
class BadInputLog
{
public:
  BadInputLog(EventCounter& events, vtkRayMapperStatistics* statistics)
    : Events(events)
    , Statistics(statistics)
    , Mark(events.Texts.size())
    , ErrorMark(events.Errors)
  {
    Statistics->ValidateFramesOn();
  }
  void Check(bool condition, const std::string& what)
  {
    std::printf("%s %s\n", condition ? "ok  " : "FAIL", what.c_str());
    Ok = Ok && condition;
  }
  /// Exactly `n` messages since the last call, all warnings, each containing `text`.
  void Warned(int n, const char* text, const std::string& what) { Messages(n, 0, text, what); }
  /// Exactly `n` messages since the last call, all errors, each containing `text`.
  void Errored(int n, const char* text, const std::string& what) { Messages(0, n, text, what); }
  /// No message since the last call.
  void Silent(const std::string& what) { Warned(0, "", what); }
  /// Exactly `warnings` + `errorsExpected` messages since the last call, `errorsExpected` of
  /// them errors, each containing `text`.
  void Messages(int warnings, int errorsExpected, const char* text, const std::string& what)
  {
    const std::vector<std::string> seen(Events.Texts.begin() + Mark, Events.Texts.end());
    Mark = Events.Texts.size();
    bool named = true;
    for (const std::string& t : seen)
    {
      named = named && t.find(text) != std::string::npos;
    }
    const int errors = Events.Errors - ErrorMark;
    ErrorMark = Events.Errors;
    Check(static_cast<int>(seen.size()) == warnings + errorsExpected && errors == errorsExpected &&
        named,
      what + ": " + std::to_string(warnings) + " warning(s) and " +
        std::to_string(errorsExpected) + " error(s) naming '" + text + "' (saw " +
        std::to_string(seen.size()) + " messages, " + std::to_string(errors) + " errors)");
  }
  /// The last render drew a frame without NaN, infinite or out-of-range values.
  void ValidFrame(const std::string& what)
  {
    const bool on = Statistics->GetEffect("frame_validation");
    const long long bad = Statistics->GetCounter("frame_nonfinite_values");
    const long long range = Statistics->GetCounter("frame_out_of_range_values");
    Check(on && bad == 0 && range == 0,
      what + ": the float frame is valid (validated " + (on ? "yes" : "NO") + ", " +
        std::to_string(bad) + " non-finite, " + std::to_string(range) + " out of range)");
  }
  /// The last render drew nothing (no frame to validate).
  void NothingDrawn(const std::string& what)
  {
    Check(!Statistics->GetEffect("frame_validation"), what + ": the mapper drew no frame");
  }
  /// The two pictures are equal, tolerance 0.
  void SameImage(const raymappers::test::RGBImage& a,
    const raymappers::test::RGBImage& b,
    const std::string& what)
  {
    const auto d = raymappers::test::compareImages(a, b, 0);
    Check(d.sameSize && d.maxError == 0,
      what + ": the same picture (max error " + std::to_string(d.maxError) + ", " +
        std::to_string(d.differing * 100.0) + "% of the pixels differ)");
  }
  bool Ok = true;

private:
  EventCounter& Events;
  vtkRayMapperStatistics* Statistics;
  std::size_t Mark = 0;
  int ErrorMark = 0;
};

/// The window's picture against a reference picture under `bound` (differing: beyond 2
/// levels); prints "ok"/"FAIL", `what` and the measured values; true when within the bound.
inline bool CheckAgainstReference(vtkRenderWindow* win,
  const raymappers::test::RGBImage& reference,
  const raymappers::test::ImageThresholds& bound,
  const char* what)
{
  const auto d = raymappers::test::compareImages(raymappers::test::fromWindow(win), reference, 2);
  const bool pass = raymappers::test::withinThresholds(d, bound);
  std::printf("%s %s against the reference: %s\n",
    pass ? "ok  " : "FAIL",
    what,
    raymappers::test::describe(d, bound).c_str());
  return pass;
}

/// The picture after VTK's own Reset Camera (the bounds of the visible props, so the
/// mapper's GetBounds, place the camera and its clipping range); the camera is put back.
inline raymappers::test::RGBImage ResetCameraImage(vtkRenderer* ren, vtkRenderWindow* win)
{
  vtkNew<vtkCamera> saved;
  saved->DeepCopy(ren->GetActiveCamera());
  ren->ResetCamera();
  win->Render();
  raymappers::test::RGBImage image = raymappers::test::fromWindow(win);
  ren->GetActiveCamera()->DeepCopy(saved);
  return image;
}

/// True when every pixel of the picture has the colour (r, g, b).
inline bool AllPixels(const raymappers::test::RGBImage& image, int r, int g, int b)
{
  for (std::size_t k = 0; k + 2 < image.rgb.size(); k += 3)
  {
    if (image.rgb[k] != r || image.rgb[k + 1] != g || image.rgb[k + 2] != b)
    {
      return false;
    }
  }
  return true;
}

/// A property set to NaN: `setup` makes the property matter (the picture with it is the
/// expectation), `bad` sets the NaN, which must give one warning and leave that picture;
/// `teardown` restores the scene.
struct NaNCase
{
  std::string name;
  std::function<void()> setup, bad, teardown;
};

/// A property set out of its range: `set(bound)` first (the picture of the bound, with
/// `boundWarnings` warnings naming `boundText` from that render), then `set(bad)`: one
/// warning containing `text`, clamped, so exactly the picture of the bound.
struct ClampCase
{
  std::string name;
  std::function<void(double)> set;
  double bad, bound;
  std::string text;
  int boundWarnings = 0;
  std::string boundText = "";
};

inline void CheckNaNCases(BadInputLog& log,
  const std::function<raymappers::test::RGBImage()>& render,
  const std::vector<NaNCase>& cases)
{
  for (const NaNCase& c : cases)
  {
    c.setup();
    const raymappers::test::RGBImage before = render();
    log.Silent(c.name + ": the setting that uses it");
    c.bad();
    log.Warned(1, "not a number", c.name + " NaN");
    log.SameImage(render(), before, c.name + " NaN: the picture before it");
    log.ValidFrame(c.name + " NaN");
    c.teardown();
  }
}

inline void CheckClampCases(BadInputLog& log,
  const std::function<raymappers::test::RGBImage()>& render,
  const std::vector<ClampCase>& cases)
{
  for (const ClampCase& c : cases)
  {
    c.set(c.bound);
    const raymappers::test::RGBImage atBound = render();
    log.Warned(c.boundWarnings, c.boundText.c_str(), c.name + " set to its bound directly");
    log.ValidFrame(c.name + " at its bound");
    c.set(c.bad);
    log.Warned(1, c.text.c_str(), c.name + " out of range");
    log.SameImage(render(), atBound, c.name + " clamped: the picture of the bound");
    log.Silent(c.name + " clamped, rendered (the state of the bound)");
    log.ValidFrame(c.name + " clamped");
  }
}

/// The degenerate cameras: a zero view angle (VTK clamps it to a tiny positive angle; the
/// mapper renders, silently, a valid frame), the eye at the focal point and a NaN position
/// (one warning each naming the camera, nothing drawn: the background `background`, no
/// new warning when rendered again, the expected picture once `restore` puts the camera
/// back).
inline void CheckDegenerateCameras(BadInputLog& log,
  vtkCamera* camera,
  const std::function<raymappers::test::RGBImage()>& render,
  const raymappers::test::RGBImage& expected,
  const std::array<int, 3>& background)
{
  const double angle = camera->GetViewAngle();
  double position[3], focal[3], up[3];
  camera->GetPosition(position);
  camera->GetFocalPoint(focal);
  camera->GetViewUp(up);
  auto restore = [&] {
    camera->SetViewAngle(angle);
    camera->SetPosition(position);
    camera->SetFocalPoint(focal);
    camera->SetViewUp(up);
  };
  camera->SetViewAngle(0);
  render();
  log.Check(camera->GetViewAngle() > 0, "VTK clamps a zero view angle to a positive one");
  log.Silent("zero view angle");
  log.ValidFrame("zero view angle");
  restore();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const auto& [what, eye] : std::vector<std::pair<std::string, std::array<double, 3>>>{
         { "eye at the focal point", { focal[0], focal[1], focal[2] } },
         { "NaN camera position", { nan, position[1], position[2] } } })
  {
    camera->SetPosition(eye.data());
    const raymappers::test::RGBImage img = render();
    log.Warned(1, "The camera is degenerate", what);
    log.NothingDrawn(what);
    log.Check(AllPixels(img, background[0], background[1], background[2]),
      what + ": the background only");
    render();
    log.Silent(what + ", rendered again");
    restore();
    log.SameImage(render(), expected, what + ", then the camera restored");
    log.Silent(what + ", then the camera restored");
  }
}

#define RM_CHECK(cond)                                                                             \
  do                                                                                               \
  {                                                                                                \
    if (!(cond))                                                                                   \
    {                                                                                              \
      std::printf("%s:%d: check failed: %s\n", __FILE__, __LINE__, #cond);                         \
      return EXIT_FAILURE;                                                                         \
    }                                                                                              \
  } while (0)

}

#endif
