// vtkCGTSphereMapper's translucent spheres against the independent reference
// (Testing/References, renderTranslucentSpheres: along each pixel's ray every sphere's first
// surface and every plane, sorted in double, composited front to back with no early
// termination, VTK's Phong model under the renderer's lights), in a real render window: 60
// random spheres with their own colours and an opacity array through a piecewise function.
//   1. the actor's Opacity 0.5 alone (coherent grid);
//   2. the opacity array (0.1 + 0.8 v through the function) times Opacity 0.8 over an
//      opaque OpenGL plane that cuts the spheres: the rays stop at its depth and the frame
//      is blended over it (coherent grid, then Embree);
//   3. a translucent OpenGL plane (opacity 0.5) through the translucent spheres, without
//      and with depth peeling: VTK composites the plane in its translucent pass, the
//      spheres are drawn over that (vtkCGTSphereMapper), so the picture is the spheres over
//      the plane; its distance to the exact composite (the plane as one more layer, sorted
//      with the spheres) is printed (measured: rmse 3.6, max error 46,
//      12.7% of the pixels beyond 2 levels, with and without depth peeling);
//   4. Opacity 1 and no opacity array: the opaque path (effect "translucency" off, no
//      translucent layer), drawn in the opaque pass.
// The measured errors are printed; the bounds leave room for early termination (at most
// 1/512 per channel), float silhouettes and the 8-bit rounding of the blending (measured:
// rmse 0.35 and 0.57 levels of 255, max error 1, no pixel beyond 2 levels), and no more.
//
// usage: TestSpheresTranslucency
#include "ReferenceFromVTK.h"
#include "ReferenceRenderers.h"
#include "RenderingTestHelpers.h"
#include "vtkCGTSphereMapper.h"
#include "vtkRayMapperStatistics.h"

#include "vtkActor.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPlaneSource.h"
#include "vtkPolyDataMapper.h"
#include "vtkProperty.h"
#include "vtkUnsignedCharArray.h"

#include <random>

namespace ref = raymappers::reference;

namespace
{
constexpr int Count = 60;

// The scene's spheres: centres in [-1, 1]^3, radii in [0.15, 0.35], colours, and the
// opacity array's values v in [0, 1].
struct Spheres
{
  vtkSmartPointer<vtkPolyData> data;
  std::vector<ref::ReferenceSphere> reference; // opacity v, scaled by the case
  std::vector<double> values;
};

Spheres MakeScene()
{
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> pos(-1, 1), rad(0.15, 0.35), unit(0, 1);
  std::vector<std::array<double, 3>> centers;
  std::vector<double> radii;
  Spheres s;
  vtkNew<vtkUnsignedCharArray> rgb;
  rgb->SetName("rgb");
  rgb->SetNumberOfComponents(3);
  vtkNew<vtkDoubleArray> alpha;
  alpha->SetName("alpha");
  for (int i = 0; i < Count; ++i)
  {
    centers.push_back({ pos(rng), pos(rng), pos(rng) });
    radii.push_back(rad(rng));
    const unsigned char c[3] = { static_cast<unsigned char>(unit(rng) * 255),
      static_cast<unsigned char>(unit(rng) * 255), static_cast<unsigned char>(unit(rng) * 255) };
    rgb->InsertNextTypedTuple(c);
    s.values.push_back(unit(rng));
    alpha->InsertNextValue(s.values.back());
    s.reference.push_back({ { centers[i][0], centers[i][1], centers[i][2] }, radii[i],
      { c[0] / 255.0, c[1] / 255.0, c[2] / 255.0 }, 1.0 });
  }
  s.data = rmtest::MakeSpheres(centers, radii);
  s.data->GetPointData()->AddArray(rgb);
  s.data->GetPointData()->AddArray(alpha);
  return s;
}

// The reference spheres with opacity `opacity` times (byArray: 0.1 + 0.8 v).
std::vector<ref::ReferenceSphere> WithOpacity(const Spheres& s, double opacity, bool byArray)
{
  std::vector<ref::ReferenceSphere> out = s.reference;
  for (std::size_t i = 0; i < out.size(); ++i)
  {
    out[i].opacity = opacity * (byArray ? 0.1 + 0.8 * s.values[i] : 1.0);
  }
  return out;
}

// An unlit plane z = -0.2 much larger than the view, of colour (0.2, 0.5, 0.3).
vtkSmartPointer<vtkActor> MakePlane(double opacity)
{
  vtkNew<vtkPlaneSource> plane;
  plane->SetOrigin(-20, -20, -0.2);
  plane->SetPoint1(20, -20, -0.2);
  plane->SetPoint2(-20, 20, -0.2);
  plane->SetResolution(8, 8);
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputConnection(plane->GetOutputPort());
  auto actor = vtkSmartPointer<vtkActor>::New();
  actor->SetMapper(mapper);
  actor->GetProperty()->LightingOff();
  actor->GetProperty()->SetColor(0.2, 0.5, 0.3);
  actor->GetProperty()->SetOpacity(opacity);
  return actor;
}

const ref::ReferencePlane PlaneLayer(double opacity)
{
  return { { 0, 0, 1 }, -0.2, { 0.2, 0.5, 0.3 }, opacity };
}

struct Scene
{
  Spheres spheres = MakeScene();
  vtkNew<vtkCGTSphereMapper> mapper;
  vtkNew<vtkActor> actor;
  vtkNew<vtkPiecewiseFunction> function;
  vtkNew<vtkRenderer> ren;
  vtkNew<vtkRenderWindow> win;
  ref::Point background{ 0.1, 0.1, 0.15 };

  Scene()
  {
    mapper->SetInputData(spheres.data);
    mapper->SetScaleArray("radius");
    mapper->SetScalarModeToUsePointFieldData();
    mapper->SelectColorArray("rgb");
    mapper->SetColorModeToDirectScalars();
    mapper->ScalarVisibilityOn();
    function->AddPoint(0, 0.1);
    function->AddPoint(1, 0.9);
    mapper->SetScalarOpacityFunction(function);
    actor->SetMapper(mapper);
    actor->GetProperty()->SetSpecular(0.3);
    actor->GetProperty()->SetSpecularPower(20);
    ren->SetBackground(background.x, background.y, background.z);
    ren->AddActor(actor);
    win->SetSize(200, 200);
    win->SetMultiSamples(0);
    win->AddRenderer(ren);
    ren->ResetCamera();
    ren->GetActiveCamera()->Azimuth(30);
    ren->GetActiveCamera()->Elevation(20);
    ren->GetActiveCamera()->Dolly(1.3);
    ren->ResetCameraClippingRange(-1.5, 1.5, -1.5, 1.5, -1.5, 1.5);
  }
  // The reference picture of the spheres with (opacity, byArray) and the planes, after
  // rendering the window.
  ref::ReferenceImage Expected(double opacity,
    bool byArray,
    const std::vector<ref::ReferencePlane>& planes)
  {
    actor->GetProperty()->SetOpacity(opacity);
    mapper->SetOpacityArray(byArray ? "alpha" : nullptr);
    win->Render();
    const std::vector<ref::ReferenceSphere> drawn =
      opacity > 0 ? WithOpacity(spheres, opacity, byArray) : std::vector<ref::ReferenceSphere>();
    return ref::renderTranslucentSpheres(ref::cameraOf(ren), drawn, ref::lightsOf(ren),
      ref::materialOf(actor->GetProperty()), planes);
  }
  // The window's picture against `expected` over the background, under `bound`.
  bool Compare(const char* what,
    const ref::ReferenceImage& expected,
    const raymappers::test::ImageThresholds& bound)
  {
    const raymappers::test::RGBImage want{ expected.width, expected.height,
      expected.over(background) };
    return rmtest::CheckAgainstReference(win, want, bound, what);
  }
  // The window's distance to `expected`, printed (no bound).
  void Measure(const char* what, const ref::ReferenceImage& expected)
  {
    const raymappers::test::RGBImage want{ expected.width, expected.height,
      expected.over(background) };
    const auto d = raymappers::test::compareImages(raymappers::test::fromWindow(win), want, 2);
    std::printf("measured %s: rmse %.4f, max error %d, %.4f%% of the pixels beyond 2 levels\n",
      what, d.rmse, d.maxError, 100.0 * d.differing);
  }
  bool Check(const char* what,
    double opacity,
    bool byArray,
    const std::vector<ref::ReferencePlane>& planes,
    const raymappers::test::ImageThresholds& bound)
  {
    return Compare(what, Expected(opacity, byArray, planes), bound);
  }
  long long Counter(const char* name) { return mapper->GetStatistics()->GetCounter(name); }
  bool Effect(const char* name) { return mapper->GetStatistics()->GetEffect(name); }
};

// `front` over `back`, premultiplied: C = C_f + (1 - A_f) C_b per pixel.
ref::ReferenceImage Over(const ref::ReferenceImage& front, const ref::ReferenceImage& back)
{
  ref::ReferenceImage out = front;
  for (std::size_t p = 0; p < out.rgba.size(); ++p)
  {
    for (int c = 0; c < 4; ++c)
    {
      out.rgba[p][c] += (1.0 - front.rgba[p][3]) * back.rgba[p][c];
    }
  }
  return out;
}

bool Report(bool condition, const char* what)
{
  std::printf("%s %s\n", condition ? "ok  " : "FAIL", what);
  return condition;
}
}

int TestSpheresTranslucency(int, char*[])
{
  Scene s;
  const raymappers::test::ImageThresholds bound{ 0.75, 0.001, 2, 3 };
  bool ok = s.Check("Opacity 0.5 (grid)", 0.5, false, {}, bound);
  ok = Report(s.Effect("translucency") && s.Counter("translucent_layers") > 0 &&
                !s.Effect("opaque_depth"),
         "translucency on, layers composited, no opaque depth to read") && ok;
  ok = Report(s.actor->HasTranslucentPolygonalGeometry() && !s.actor->HasOpaqueGeometry(),
         "the actor of Opacity 0.5 is translucent") && ok;

  vtkSmartPointer<vtkActor> opaquePlane = MakePlane(1.0);
  s.ren->AddActor(opaquePlane);
  ok = s.Check("opacity array x 0.8 over an opaque plane (grid)", 0.8, true, { PlaneLayer(1) },
         bound) && ok;
  ok = Report(s.Effect("opaque_depth"), "the opaque plane's depth is read") && ok;
  ok = Report(s.mapper->HasTranslucentPolygonalGeometry() && !s.mapper->HasOpaqueGeometry(),
         "the mapper with an opacity array is translucent") && ok;
  s.mapper->SetAcceleratorToEmbree();
  ok = s.Check("opacity array x 0.8 over an opaque plane (Embree)", 0.8, true, { PlaneLayer(1) },
         bound) && ok;
  s.mapper->SetAcceleratorToCoherentGrid();
  s.ren->RemoveActor(opaquePlane);

  // A translucent OpenGL plane through the spheres: VTK composites it in its translucent
  // pass (order-independent blending, or depth peeling), and the spheres are drawn over the
  // result, so the plane shows behind every sphere: the picture is the spheres over the
  // plane, not the exact composite (whose error is measured and printed).
  vtkSmartPointer<vtkActor> glass = MakePlane(0.5);
  s.ren->AddActor(glass);
  for (const int peeling : { 0, 1 })
  {
    s.ren->SetUseDepthPeeling(peeling);
    s.ren->SetMaximumNumberOfPeels(8);
    s.ren->SetOcclusionRatio(0);
    const ref::ReferenceImage exact = s.Expected(0.8, true, { PlaneLayer(0.5) });
    s.Measure(peeling ? "glass plane, depth peeling, against the exact composite"
                      : "glass plane, no depth peeling, against the exact composite",
      exact);
    const ref::ReferenceImage over =
      Over(s.Expected(0.8, true, {}), s.Expected(0.0, false, { PlaneLayer(0.5) }));
    s.actor->GetProperty()->SetOpacity(0.8);
    s.win->Render();
    ok = s.Compare(peeling ? "glass plane, depth peeling: the spheres over the plane"
                           : "glass plane, no depth peeling: the spheres over the plane",
           over, bound) && ok;
  }
  s.ren->RemoveActor(glass);
  s.ren->SetUseDepthPeeling(0);

  s.actor->GetProperty()->SetOpacity(1.0);
  s.mapper->SetOpacityArray(nullptr);
  s.win->Render();
  ok = Report(!s.Effect("translucency") && s.Counter("translucent_layers") == 0 &&
                s.Counter("translucent_queries") == 0 && s.actor->HasOpaqueGeometry() &&
                !s.actor->HasTranslucentPolygonalGeometry(),
         "Opacity 1 without an opacity array: the opaque path, in the opaque pass") && ok;
  return ok ? EXIT_SUCCESS : EXIT_FAILURE;
}
