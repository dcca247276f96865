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

#include <cmath>
#include <cstdio>
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

private:
  static void On(vtkObject*, unsigned long event, void* self, void* text)
  {
    auto* me = static_cast<EventCounter*>(self);
    (event == vtkCommand::WarningEvent ? me->Warnings : me->Errors)++;
    me->Last = text ? static_cast<const char*>(text) : "";
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
