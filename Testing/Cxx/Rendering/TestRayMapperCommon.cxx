// The shared VTK adapters of Mappers/Common, against closed forms:
//  - the opaque depth read back from an OpenGL plane, turned into distances along our
//    primary rays, equals the analytic ray-plane distance;
//  - a frame drawn in blend mode composites premultiplied colour over the framebuffer,
//    src + (1 - src.a) dst; in opaque mode it writes depth and is hidden where an
//    ordinary polygon is nearer;
//  - transfer functions sampled from a vtkVolumeProperty and a lookup table;
//  - which props make the volume mappers read the depth buffer (HasOpaqueGeometry).
#include "RenderingTestHelpers.h"
#include "vtkRayMapperFrameDrawer.h"
#include "vtkRayMapperRenderHelpers.h"

#include "vtkActor.h"
#include "vtkColorTransferFunction.h"
#include "vtkLookupTable.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPlaneSource.h"
#include "vtkPolyDataMapper.h"
#include "vtkProperty.h"
#include "vtkRBFVolumeMapper.h"
#include "vtkSPHFluidMapper.h"
#include "vtkTextActor.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"

namespace
{
// Draws a frame through the drawer at the end of the renderer's render (context current).
struct FrameOverlay
{
  vtkRayMapperFrameDrawer Drawer;
  raymappers::Frame Frame;
  vtkRayMapperFrameDrawer::Mode Mode = vtkRayMapperFrameDrawer::Mode::BlendPremultiplied;
  static void Draw(vtkObject* caller, unsigned long, void* self, void*)
  {
    auto* me = static_cast<FrameOverlay*>(self);
    raymappers::RenderStatistics unused;
    me->Drawer.Draw(static_cast<vtkRenderer*>(caller), me->Frame, me->Mode, false, unused);
  }
};

std::array<int, 3> Pixel(vtkRenderWindow* win, int x, int y)
{
  unsigned char* p = win->GetPixelData(x, y, x, y, 0);
  std::array<int, 3> c{ p[0], p[1], p[2] };
  delete[] p;
  return c;
}
}

int TestRayMapperCommon(int, char*[])
{
  // A white unlit plane z = -1 (x, y in [-1, 1]) seen from (0.3, 0.2, 4).
  vtkNew<vtkPlaneSource> plane;
  plane->SetOrigin(-1, -1, -1);
  plane->SetPoint1(1, -1, -1);
  plane->SetPoint2(-1, 1, -1);
  vtkNew<vtkPolyDataMapper> pm;
  pm->SetInputConnection(plane->GetOutputPort());
  vtkNew<vtkActor> pa;
  pa->SetMapper(pm);
  pa->GetProperty()->LightingOff();
  pa->GetProperty()->SetColor(1, 1, 1);
  vtkNew<vtkRenderer> ren;
  ren->AddActor(pa);
  ren->SetBackground(0, 0, 0);
  vtkNew<vtkRenderWindow> win;
  win->SetSize(200, 160);
  // With multisampling (VTK's default is 8 samples) the depth read back is one sample's,
  // not the pixel centre's: off, it is the depth at the centre, where our rays go.
  win->SetMultiSamples(0);
  win->AddRenderer(ren);
  ren->GetActiveCamera()->SetPosition(0.3, 0.2, 4);
  ren->GetActiveCamera()->SetFocalPoint(0, 0, -1);
  ren->ResetCameraClippingRange();
  win->Render();

  // 1. Depth read-back: window depth -> distance along our ray = ray-plane distance.
  std::vector<float> depth;
  int w = 0, h = 0;
  RM_CHECK(vtkRayMapperRenderHelpers::ReadOpaqueDepth(ren, depth, w, h));
  RM_CHECK(w == 200 && h == 160);
  const auto model = vtkRayMapperRenderHelpers::GatherModelTransform(pa);
  const raymappers::RayCamera camera =
    vtkRayMapperRenderHelpers::GatherCamera(ren, model, raymappers::Vec3d(0, 0, 0));
  double worst = 0;
  int onPlane = 0;
  for (int j = 5; j < h; j += 15)
  {
    for (int i = 5; i < w; i += 15)
    {
      const float d = depth[static_cast<std::size_t>(j * w + i)];
      const raymappers::Ray ray = camera.pixelRay(i, j);
      const double t = (-1.0 - ray.org.z) / ray.dir.z; // the ray meets z = -1 at t
      const double x = ray.org.x + t * ray.dir.x, y = ray.org.y + t * ray.dir.y;
      const bool inside = std::fabs(x) < 0.98 && std::fabs(y) < 0.98;
      if (!inside)
      {
        continue;
      }
      ++onPlane;
      const double tBuffer = camera.depthMap(ray).distanceOf(d);
      worst = std::max(worst, std::fabs(tBuffer - t) / t);
    }
  }
  std::printf("depth read-back: %d pixels on the plane, worst relative distance error %.2e\n",
    onPlane,
    worst);
  RM_CHECK(onPlane > 50);
  RM_CHECK(worst < 1e-4); // 24-bit depth buffer

  // 2. Blend mode: premultiplied (0.25, 0, 0, 0.5) over white = (0.75, 0.5, 0.5).
  FrameOverlay overlay;
  overlay.Frame.resize(w, h);
  for (std::size_t k = 0; k < overlay.Frame.depth.size(); ++k)
  {
    overlay.Frame.rgba[4 * k] = 0.25f;
    overlay.Frame.rgba[4 * k + 3] = 0.5f;
  }
  vtkNew<vtkCallbackCommand> cb;
  cb->SetClientData(&overlay);
  cb->SetCallback(&FrameOverlay::Draw);
  ren->AddObserver(vtkCommand::EndEvent, cb);
  win->Render();
  const auto centre = Pixel(win, 100, 80);
  const auto corner = Pixel(win, 1, 1);
  std::printf("blend: over the plane (%d %d %d), over the background (%d %d %d)\n",
    centre[0],
    centre[1],
    centre[2],
    corner[0],
    corner[1],
    corner[2]);
  RM_CHECK(std::abs(centre[0] - 191) <= 1 && std::abs(centre[1] - 128) <= 1);
  RM_CHECK(std::abs(corner[0] - 64) <= 1 && corner[1] == 0);
  // The next frame of the same size goes into the texture the first one left (the drawer
  // keeps its storage): premultiplied (0, 0.25, 0, 0.5) over white = (0.5, 0.75, 0.5). Then
  // a smaller window and frame take new storage: the frame covers the whole window again.
  for (std::size_t k = 0; k < overlay.Frame.depth.size(); ++k)
  {
    overlay.Frame.rgba[4 * k] = 0.f;
    overlay.Frame.rgba[4 * k + 1] = 0.25f;
  }
  win->Render();
  const auto second = Pixel(win, 100, 80);
  std::printf("blend, next frame: (%d %d %d)\n", second[0], second[1], second[2]);
  RM_CHECK(std::abs(second[0] - 128) <= 1 && std::abs(second[1] - 191) <= 1);
  win->SetSize(120, 100);
  overlay.Frame.resize(120, 100);
  for (std::size_t k = 0; k < overlay.Frame.depth.size(); ++k)
  {
    overlay.Frame.rgba[4 * k + 2] = 0.5f;
    overlay.Frame.rgba[4 * k + 3] = 0.5f;
  }
  win->Render();
  const auto resized = Pixel(win, 118, 98), resizedCorner = Pixel(win, 1, 1);
  std::printf("blend, resized window: top right (%d %d %d), bottom left (%d %d %d)\n",
    resized[0], resized[1], resized[2], resizedCorner[0], resizedCorner[1], resizedCorner[2]);
  RM_CHECK(resized[0] == 0 && std::abs(resized[2] - 128) <= 1);
  RM_CHECK(resizedCorner[0] == 0 && std::abs(resizedCorner[2] - 128) <= 1);
  win->SetSize(200, 160);
  overlay.Frame.resize(w, h);

  // 3. Opaque mode: a green frame just in front of the plane's depth shows; just behind
  //    it, the plane hides it.
  const float planeDepthAtCentre = depth[static_cast<std::size_t>(80 * w + 100)];
  for (std::size_t k = 0; k < overlay.Frame.depth.size(); ++k)
  {
    overlay.Frame.rgba[4 * k] = 0.f;
    overlay.Frame.rgba[4 * k + 1] = 1.f;
    overlay.Frame.rgba[4 * k + 3] = 1.f;
    overlay.Frame.depth[k] = planeDepthAtCentre - 0.02f; // in front of the plane
  }
  overlay.Mode = vtkRayMapperFrameDrawer::Mode::OpaqueWithDepth;
  win->Render();
  const auto c2 = Pixel(win, 100, 80);
  std::printf("opaque: plane depth at the centre %.4f, frame in front: pixel (%d %d %d)\n",
    planeDepthAtCentre,
    c2[0],
    c2[1],
    c2[2]);
  RM_CHECK(c2[0] == 0 && c2[1] == 255 && c2[2] == 0);
  for (std::size_t k = 0; k < overlay.Frame.depth.size(); ++k)
  {
    overlay.Frame.depth[k] = planeDepthAtCentre + 0.02f; // behind the plane
  }
  win->Render();
  const auto c3 = Pixel(win, 100, 80);
  RM_CHECK(c3[0] == 255 && c3[1] == 255); // the white plane hides the frame
  ren->RemoveObserver(cb);
  overlay.Drawer.ReleaseGraphicsResources(win);

  // 4. Transfer functions: colour ramp (10 -> blue, 30 -> red), opacity ramp 0 -> 0.8.
  vtkNew<vtkColorTransferFunction> ctf;
  ctf->AddRGBPoint(10, 0, 0, 1);
  ctf->AddRGBPoint(30, 1, 0, 0);
  vtkNew<vtkPiecewiseFunction> otf;
  otf->AddPoint(10, 0.0);
  otf->AddPoint(30, 0.8);
  vtkNew<vtkVolumeProperty> vp;
  vp->SetColor(ctf);
  vp->SetScalarOpacity(otf);
  vp->SetScalarOpacityUnitDistance(2.5);
  const auto table = vtkRayMapperRenderHelpers::SampleVolumeProperty(vp, 0, 256);
  RM_CHECK(table.rangeMin() == 10 && table.rangeMax() == 30);
  RM_CHECK(table.unitDistance() == 2.5);
  for (double v : { 10.0, 12.5, 20.0, 27.3, 30.0 })
  {
    const auto c = table.lookup(v);
    const double f = (v - 10) / 20;
    RM_CHECK(std::fabs(c[0] - f) < 1e-3 && std::fabs(c[2] - (1 - f)) < 1e-3);
    RM_CHECK(std::fabs(c[3] - 0.8 * f) < 1e-3);
  }
  vtkNew<vtkLookupTable> lut;
  lut->SetRange(-1, 1);
  lut->SetHueRange(0.0, 0.667);
  lut->Build();
  const auto lt = vtkRayMapperRenderHelpers::SampleScalarsToColors(lut, -1, 1, 256);
  for (double v : { -1.0, -0.3, 0.0, 0.77, 1.0 })
  {
    double rgb[3];
    lut->GetColor(v, rgb);
    const auto c = lt.lookup(v);
    RM_CHECK(std::fabs(c[0] - rgb[0]) < 0.02 && std::fabs(c[2] - rgb[2]) < 0.02);
  }
  // Opaque geometry for the volume mappers: a volume writes no depth, nor does a 2D
  // overlay; an actor with opaque geometry and the SPH fluid's surface do.
  {
    vtkNew<vtkRenderer> scene;
    vtkNew<vtkVolume> cloud;
    vtkNew<vtkRBFVolumeMapper> cloudMapper;
    cloud->SetMapper(cloudMapper);
    scene->AddVolume(cloud);
    vtkNew<vtkTextActor> label;
    scene->AddActor2D(label);
    RM_CHECK(!vtkRayMapperRenderHelpers::HasOpaqueGeometry(scene));
    vtkNew<vtkVolume> fluid;
    vtkNew<vtkSPHFluidMapper> fluidMapper;
    fluid->SetMapper(fluidMapper);
    scene->AddVolume(fluid);
    RM_CHECK(vtkRayMapperRenderHelpers::HasOpaqueGeometry(scene));
    fluid->VisibilityOff();
    RM_CHECK(!vtkRayMapperRenderHelpers::HasOpaqueGeometry(scene));
    scene->AddActor(pa);
    RM_CHECK(vtkRayMapperRenderHelpers::HasOpaqueGeometry(scene));
    pa->VisibilityOff();
    RM_CHECK(!vtkRayMapperRenderHelpers::HasOpaqueGeometry(scene));
  }
  std::printf("common adapters: all checks passed\n");
  return EXIT_SUCCESS;
}
