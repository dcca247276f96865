// vtkSPHFluidMapper on a PySPH dam break (Data/dam_break_coarse_00674.vtk, t = 0.3 s, the
// particles as spheres of radius 0.8 h): every particle used without warnings; only the
// effects asked for run (no refraction march at index 1, no AO work when off, no smoothing
// pass at radius 0), and each changes the picture when on; a new time step rebuilds the
// particles and a camera move does not; vtkSPHVoxelizer with the renderer's camera finds
// the spans the mapper rendered; an opaque sphere in front hides the fluid (translucent and
// opaque); the picture matches the baseline. Then a closed-form case: one sphere of radius 1
// with a black fluid colour and grey absorption kappa over a white background shows
// exp(-kappa 2) of it on the central pixel, and exp(-kappa 1) when an opaque white plane
// through the centre ends the fluid there; a white fluid with the default coloured absorption
// over black shows omega_c (1 - exp(-kappa_c 2)) per channel, omega_c = min_k kappa_k /
// kappa_c. Last, colouring by a point array (CheckColorBy).
//
// usage: TestSPHFluidMapper -D <Data dir> -T <tmp> -V <png>
#include "RenderingTestHelpers.h"
#include "vtkRayMapperStatistics.h"
#include "vtkSPHFluidMapper.h"
#include "vtkSPHVoxelizer.h"

#include "vtkActor.h"
#include "vtkDoubleArray.h"
#include "vtkImageData.h"
#include "vtkLookupTable.h"
#include "vtkPointData.h"
#include "vtkPlaneSource.h"
#include "vtkPolyDataMapper.h"
#include "vtkPolyDataReader.h"
#include "vtkProperty.h"
#include "vtkSphereSource.h"
#include "vtkTestUtilities.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"

#include <algorithm>
#include <cmath>

namespace
{
double MeanDifference(const std::vector<unsigned char>& a, const std::vector<unsigned char>& b)
{
  double sum = 0;
  for (std::size_t k = 0; k < a.size(); ++k)
  {
    sum += std::abs(int(a[k]) - int(b[k]));
  }
  return sum / static_cast<double>(a.size());
}

const unsigned char* Pixel(const std::vector<unsigned char>& rgb, int width, int i, int j)
{
  return &rgb[3 * (static_cast<std::size_t>(j) * width + i)];
}

// Closed form: Beer-Lambert through one sphere of radius `scale` (Density 1 per particle
// radius, so the same transmittance at every scale), and stopped by a plane through it.
bool CheckBeerLambert(double scale)
{
  bool ok = true;
  auto check = [&](bool condition, const char* what) {
    std::printf("%s %s\n", condition ? "ok  " : "FAIL", what);
    ok = ok && condition;
  };
  auto one = rmtest::MakeSpheres({ { 0.0, 0.0, 0.0 } }, { scale });
  vtkNew<vtkSPHFluidMapper> fluid;
  fluid->SetInputData(one);
  fluid->SetRadius(scale);
  fluid->SetDensity(1); // per particle radius: kappa per radius, whatever the units
  fluid->SetSmoothingRadius(0);
  fluid->SetColor(0, 0, 0);
  const double kappa = 0.6;
  fluid->SetAbsorptionColor(kappa, kappa, kappa);
  fluid->SetAngleResolution(2.0);
  vtkNew<vtkVolume> v;
  v->SetMapper(fluid);
  vtkNew<vtkVolumeProperty> flat;
  flat->SetSpecular(0);
  v->SetProperty(flat);
  vtkNew<vtkRenderer> r2;
  r2->SetBackground(1, 1, 1);
  r2->AddVolume(v);
  vtkNew<vtkRenderWindow> w2;
  w2->SetSize(101, 101);
  w2->AddRenderer(r2);
  r2->GetActiveCamera()->SetPosition(0, 0, 6 * scale);
  r2->GetActiveCamera()->SetFocalPoint(0, 0, 0);
  r2->ResetCameraClippingRange();
  w2->Render();
  auto rgb = rmtest::ReadRGB(w2);
  const unsigned char* centre = Pixel(rgb, 101, 50, 50);
  const double expected = 255 * std::exp(-kappa * 2.0);
  std::printf("radius %g, through the sphere: %d %d %d, exp(-kappa 2) = %.1f\n", scale, centre[0], centre[1],
    centre[2], expected);
  check(std::abs(centre[0] - expected) <= 2 && centre[1] == centre[0] && centre[2] == centre[0],
    "the background shows through by exp(-kappa l), l = 2r");
  // An unlit white plane z = 0 behind the sphere's front half.
  vtkNew<vtkPlaneSource> plane;
  plane->SetOrigin(-3 * scale, -3 * scale, 0);
  plane->SetPoint1(3 * scale, -3 * scale, 0);
  plane->SetPoint2(-3 * scale, 3 * scale, 0);
  vtkNew<vtkPolyDataMapper> planeMapper;
  planeMapper->SetInputConnection(plane->GetOutputPort());
  vtkNew<vtkActor> planeActor;
  planeActor->SetMapper(planeMapper);
  planeActor->GetProperty()->SetColor(1, 1, 1);
  planeActor->GetProperty()->SetAmbient(1);
  planeActor->GetProperty()->SetDiffuse(0);
  planeActor->GetProperty()->SetSpecular(0);
  r2->AddActor(planeActor);
  r2->ResetCameraClippingRange();
  w2->Render();
  rgb = rmtest::ReadRGB(w2);
  centre = Pixel(rgb, 101, 50, 50);
  const double half = 255 * std::exp(-kappa * 1.0);
  std::printf("to the plane: %d %d %d, exp(-kappa 1) = %.1f\n", centre[0], centre[1], centre[2],
    half);
  check(std::abs(centre[0] - half) <= 2, "an opaque plane through the centre: exp(-kappa r)");
  // A white fluid with the default coloured absorption kappa = (0.8, 0.35, 0.15) per radius,
  // unlit, over black: through the 2 radii at the centre the medium sends back
  // omega_c (1 - exp(-2 kappa_c)), omega_c = min_k kappa_k / kappa_c (in closed form here).
  fluid->SetColor(1, 1, 1);
  fluid->SetAbsorptionColor(0.8, 0.35, 0.15);
  flat->SetAmbient(1);
  flat->SetDiffuse(0);
  r2->RemoveActor(planeActor);
  r2->SetBackground(0, 0, 0);
  w2->Render();
  rgb = rmtest::ReadRGB(w2);
  centre = Pixel(rgb, 101, 50, 50);
  const double k[3] = { 0.8, 0.35, 0.15 };
  bool tinted = true;
  for (int c = 0; c < 3; ++c)
  {
    const double body = 255 * (0.15 / k[c]) * (1 - std::exp(-2 * k[c]));
    std::printf("channel %d: %d, omega (1 - exp(-2 kappa)) = %.1f\n", c, centre[c], body);
    tinted = tinted && std::abs(centre[c] - body) <= 2;
  }
  check(tinted, "coloured absorption: the albedo's tint, omega (1 - T), per channel");
  return ok;
}

// Colouring by scalars: a block of particles, "side" 0 for x < 0 and 1 beyond, opaque and
// unlit (ambient 1), mapped through a red-to-blue lookup table: the fluid shows the table's
// colour of each side away from the middle (the kernel average there holds one side's
// particles only), a mix in the middle; the solid Color without ScalarVisibility; one warning
// and the solid Color for a missing array.
bool CheckColorBy()
{
  bool ok = true;
  auto check = [&](bool condition, const char* what) {
    std::printf("%s %s\n", condition ? "ok  " : "FAIL", what);
    ok = ok && condition;
  };
  std::vector<std::array<double, 3>> centres;
  for (int i = -8; i < 8; ++i)
    for (int j = -3; j <= 3; ++j)
      for (int k = -3; k <= 3; ++k)
        centres.push_back({ (i + 0.5) * 0.1, j * 0.1, k * 0.1 });
  auto block = rmtest::MakeSpheres(centres, std::vector<double>(centres.size(), 0.1));
  vtkNew<vtkDoubleArray> side;
  side->SetName("side");
  for (const auto& c : centres)
  {
    side->InsertNextValue(c[0] < 0 ? 0.0 : 1.0);
  }
  block->GetPointData()->AddArray(side);
  vtkNew<vtkLookupTable> lut;
  lut->SetRange(0, 1);
  lut->SetHueRange(0.0, 0.6667); // red to blue
  lut->Build();
  vtkNew<vtkSPHFluidMapper> fluid;
  fluid->SetInputData(block);
  fluid->SetRadius(0.1);
  fluid->TranslucencyOff();
  fluid->SetColor(0.2, 0.8, 0.2);
  fluid->SetLookupTable(lut);
  fluid->SetColorArrayName("side");
  fluid->ScalarVisibilityOn();
  rmtest::EventCounter events;
  events.Observe(fluid);
  vtkNew<vtkVolumeProperty> unlit;
  unlit->SetAmbient(1);
  unlit->SetDiffuse(0);
  unlit->SetSpecular(0);
  vtkNew<vtkVolume> v;
  v->SetMapper(fluid);
  v->SetProperty(unlit);
  vtkNew<vtkRenderer> r;
  r->AddVolume(v);
  vtkNew<vtkRenderWindow> w;
  w->SetSize(200, 100);
  w->AddRenderer(r);
  r->GetActiveCamera()->SetPosition(0, 0, 4);
  r->GetActiveCamera()->SetFocalPoint(0, 0, 0);
  r->ResetCameraClippingRange();
  w->Render();
  auto rgb = rmtest::ReadRGB(w);
  double left[3], right[3], middle[3], x0[3] = { -0.55, 0, 0.3 }, x1[3] = { 0.55, 0, 0.3 },
                                        xm[3] = { 0, 0, 0.3 };
  rmtest::DisplayOf(r, x0, left);
  rmtest::DisplayOf(r, x1, right);
  rmtest::DisplayOf(r, xm, middle);
  auto at = [&](const double* d) { return Pixel(rgb, 200, int(d[0]), int(d[1])); };
  const unsigned char *a = at(left), *b = at(right), *m = at(middle);
  std::printf("by side: left %d %d %d, right %d %d %d, middle %d %d %d\n", a[0], a[1], a[2], b[0],
    b[1], b[2], m[0], m[1], m[2]);
  vtkRayMapperStatistics* stats = fluid->GetStatistics();
  check(a[0] >= 253 && a[1] <= 2 && a[2] <= 2 && b[0] <= 2 && b[1] <= 2 && b[2] >= 253,
    "coloured by side: the table's red on the left, its blue on the right");
  check(m[0] > 40 && m[2] > 40 && stats->GetEffect("particle_colors") &&
      stats->GetCounter("colors_built") == 1,
    "between the sides the kernel average mixes them");
  w->Render();
  check(stats->GetCounter("colors_built") == 0, "a second frame reuses the colours");
  lut->SetHueRange(0.6667, 0.0);
  lut->Build();
  w->Render();
  rgb = rmtest::ReadRGB(w);
  check(stats->GetCounter("colors_built") == 1 && at(left)[2] >= 253 && at(right)[0] >= 253,
    "a new lookup table recolours");
  fluid->ScalarVisibilityOff();
  w->Render();
  rgb = rmtest::ReadRGB(w);
  const unsigned char* solid = at(left);
  check(std::abs(solid[0] - 51) <= 1 && std::abs(solid[1] - 204) <= 1 &&
      !stats->GetEffect("particle_colors") && stats->GetCounter("color_samples") == 0 &&
      events.Warnings == 0,
    "ScalarVisibility off: the solid Color, nothing looked up");
  fluid->ScalarVisibilityOn();
  fluid->SetColorArrayName("missing");
  w->Render();
  rgb = rmtest::ReadRGB(w);
  check(events.Warnings == 1 && at(left)[1] >= 203 && !stats->GetEffect("particle_colors"),
    "a missing colour array: one warning, the solid Color");
  return ok;
}
}

int TestSPHFluidMapper(int argc, char* argv[])
{
  char* file = vtkTestUtilities::ExpandDataFileName(argc, argv, "dam_break_coarse_00674.vtk");
  vtkNew<vtkPolyDataReader> reader;
  reader->SetFileName(file);
  reader->ReadAllScalarsOn(); // the file has one SCALARS section per array
  reader->Update();
  delete[] file;
  vtkPolyData* particles = reader->GetOutput();
  if (particles->GetNumberOfPoints() != 9360)
  {
    std::printf("FAIL: the dam break was not read\n");
    return EXIT_FAILURE;
  }

  vtkNew<vtkSPHFluidMapper> mapper;
  mapper->SetInputData(particles);
  mapper->SetRadiusArrayName("h");
  mapper->SetRadiusScale(0.8);
  mapper->SetAbsorptionColor(4.0, 1.5, 0.8);
  // World lengths, as the baselines were made: absorption 1 per unit, no smoothing unless
  // set below (TestSPHFluidRelativeLengths covers the relative defaults).
  mapper->SetLengthUnitToWorld();
  mapper->SetDensity(1);
  mapper->SetSmoothingRadius(0);
  vtkNew<vtkVolumeProperty> property;
  property->SetAmbient(0.25);
  property->SetDiffuse(0.75);
  property->SetSpecular(0.3);
  property->SetSpecularPower(40);
  vtkNew<vtkVolume> volume;
  volume->SetMapper(mapper);
  volume->SetProperty(property);
  vtkNew<vtkRenderer> ren;
  ren->SetBackground(0.1, 0.1, 0.15);
  ren->AddVolume(volume);
  vtkNew<vtkRenderWindow> win;
  win->SetSize(400, 300);
  win->AddRenderer(ren);
  rmtest::EventCounter events;
  events.Observe(mapper);
  vtkCamera* camera = ren->GetActiveCamera();
  camera->SetFocalPoint(0.9, 0.0, 0.2);
  camera->SetPosition(0.2, -2.6, 1.5);
  camera->SetViewUp(0, 0, 1);
  ren->ResetCameraClippingRange();

  bool ok = true;
  auto check = [&](bool condition, const char* what) {
    std::printf("%s %s\n", condition ? "ok  " : "FAIL", what);
    ok = ok && condition;
  };
  auto render = [&]() {
    win->Render();
    return rmtest::ReadRGB(win);
  };
  vtkRayMapperStatistics* stats = mapper->GetStatistics();
  auto counter = [&](const char* name) { return stats->GetCounter(name); };

  // Translucency alone: no march, no AO, no smoothing.
  const auto picture = render();
  std::printf("%s", stats->GetSummary());
  check(counter("particles") == 9360 && counter("particles_skipped") == 0 && events.Warnings == 0 &&
      events.Errors == 0,
    "every particle used, no warning");
  check(counter("particles_built") == 1 && counter("translucent_pixels") > 10000 &&
      counter("translucent_pixels") == counter("shaded_pixels"),
    "translucent: every fluid pixel absorbs over its spans");
  check(counter("march_columns") == 0 && counter("refraction_paths") == 0 &&
      !stats->GetEffect("refraction"),
    "index 1: no refraction march");
  check(counter("ao_samples") == 0 && stats->GetPhaseTime("ao") == 0 &&
      !stats->GetEffect("ambient_occlusion"),
    "AO off: no AO work");
  check(counter("filter_iterations") == 0 && counter("filtered_points") == 0 &&
      !stats->GetEffect("smoothing"),
    "smoothing radius 0: no smoothing pass");
  check(counter("spans_found") >= counter("spans_stored") && counter("spans_stored") > 0 &&
      counter("layers") > 1000,
    "spans over more than a thousand layers");

  // The same view again: the particles are not rebuilt.
  const auto again = render();
  check(counter("particles_built") == 0 && counter("cells_built") == 0 && again == picture,
    "a second frame: no rebuild, same picture");

  // Boundary-cell culling (on by default) leaves out the inner cells' particles and fills the
  // full cells instead: the spans, and so the picture, are the same as without it.
  {
    const long long splatted = counter("particles_in_view"), spans = counter("spans_found");
    check(stats->GetEffect("boundary_culling") && counter("culled_particles") > 0 &&
        counter("inner_cells") > 0 && counter("boxes_in_view") > 0 &&
        splatted + counter("culled_particles") == 9360,
      "culling: inner cells' particles not splatted");
    mapper->BoundaryCullingOff();
    const auto plain = render();
    check(counter("cells_built") == 1 && counter("culled_particles") == 0 &&
        counter("particles_in_view") == 9360 && counter("spans_found") == spans && plain == picture,
      "without culling: every particle splatted, same spans, same picture");
    mapper->BoundaryCullingOn();
  }

  // vtkSPHVoxelizer with this camera and size voxelizes exactly what the mapper rendered.
  {
    vtkNew<vtkSPHVoxelizer> voxelizer;
    voxelizer->SetInputData(particles);
    voxelizer->SetRadiusArrayName("h");
    voxelizer->SetRadiusScale(0.8);
    voxelizer->SetCamera(camera);
    voxelizer->ResetCameraOff();
    voxelizer->SetImageSize(400, 300);
    voxelizer->Update();
    vtkDataArray* count = voxelizer->GetOutput()->GetPointData()->GetArray("SpanCount");
    long long stored = 0, pixels = 0;
    for (vtkIdType p = 0; p < count->GetNumberOfTuples(); ++p)
    {
      stored += static_cast<long long>(count->GetTuple1(p));
      pixels += count->GetTuple1(p) > 0;
    }
    std::printf("voxelizer: %lld spans on %lld pixels; mapper: %lld spans, %lld pixels\n", stored,
      pixels, counter("spans_stored"), counter("shaded_pixels"));
    check(stored == counter("spans_stored") && pixels == counter("shaded_pixels"),
      "the filter's spans are the mapper's");
  }

  // Interactive renders: p x p fewer pixels, enlarged, when the last full frame overran the
  // budget; a still render gives the full picture back.
  {
    mapper->AutoAdjustSampleDistancesOff();
    mapper->SetImageSampleDistance(2.0);
    const auto reduced = render();
    const double off = MeanDifference(reduced, picture);
    std::printf("image sample distance 2: mean difference to the full picture %.3f\n", off);
    check(counter("image_sample_distance_percent") == 200 && off > 0 && off < 3.0,
      "ImageSampleDistance 2: an approximation of the full picture");
    mapper->AutoAdjustSampleDistancesOn();
    win->SetDesiredUpdateRate(1e9); // an interactive render with a 1 ns budget
    render();
    check(counter("image_sample_distance_percent") == 800,
      "interactive, the last frame over budget: MaximumImageSampleDistance 8");
    mapper->SetFrameBudget(1e6); // an interactive render with a budget no frame overruns
    check(render() == picture && counter("image_sample_distance_percent") == 100,
      "interactive within the budget: MinimumImageSampleDistance, the full picture");
    mapper->SetFrameBudget(0);
    win->SetDesiredUpdateRate(0.0001); // a still render
    check(render() == picture && counter("image_sample_distance_percent") == 100,
      "a still render: the full picture");
  }

  // Each effect on alone changes the picture and does its work.
  mapper->SetSmoothingRadius(0.03);
  const auto smoothed = render();
  check(counter("filter_iterations") > 0 && counter("filtered_points") > 0 &&
      MeanDifference(smoothed, picture) > 0.05,
    "smoothing radius 0.03: a smoothing pass, another picture");
  mapper->SetSmoothingRadius(0);
  mapper->AmbientOcclusionOn();
  mapper->SetAmbientOcclusionRadius(0.08);
  const auto occluded = render();
  check(counter("ao_samples") == 16 * counter("shaded_pixels") &&
      MeanDifference(occluded, picture) > 0.05,
    "AO on: 16 samples per fluid pixel, another picture");
  mapper->AmbientOcclusionOff();
  mapper->SetRefractiveIndex(1.33);
  const auto refracted = render();
  check(counter("refraction_paths") == counter("shaded_pixels") && counter("march_columns") > 0 &&
      counter("translucent_pixels") == 0 && MeanDifference(refracted, picture) > 0.5,
    "index 1.33: refraction paths marched through the columns, another picture");
  mapper->SetRefractiveIndex(1.0);

  // A time step: moved points rebuild the particles.
  vtkNew<vtkPolyData> moved;
  moved->DeepCopy(particles);
  for (vtkIdType i = 0; i < moved->GetNumberOfPoints(); ++i)
  {
    double p[3];
    moved->GetPoint(i, p);
    p[0] += 0.3;
    moved->GetPoints()->SetPoint(i, p);
  }
  mapper->SetInputData(moved);
  const auto shifted = render();
  check(counter("particles_built") == 1 && MeanDifference(shifted, picture) > 1.0,
    "new time step: particles rebuilt, the fluid moved");
  moved->GetPoints()->Modified();
  render();
  check(counter("particles_built") == 1, "points modified in place: rebuilt");
  mapper->SetInputData(particles);

  // An opaque sphere in front of the water column hides it, translucent or opaque.
  vtkNew<vtkSphereSource> sphere;
  sphere->SetCenter(0.35, -0.45, 0.2);
  sphere->SetRadius(0.1);
  sphere->SetThetaResolution(48);
  sphere->SetPhiResolution(48);
  vtkNew<vtkPolyDataMapper> sphereMapper;
  sphereMapper->SetInputConnection(sphere->GetOutputPort());
  vtkNew<vtkActor> actor;
  actor->SetMapper(sphereMapper);
  actor->GetProperty()->SetColor(1, 1, 0);
  ren->AddActor(actor);
  double c[3] = { 0.35, -0.45, 0.2 }, d[3];
  rmtest::DisplayOf(ren, c, d);
  const int ci = static_cast<int>(d[0]), cj = static_cast<int>(d[1]);
  volume->VisibilityOff();
  const auto sphereAlone = render();
  volume->VisibilityOn();
  const auto sphereAndFluid = render();
  const unsigned char* a = Pixel(sphereAlone, 400, ci, cj);
  const unsigned char* b = Pixel(sphereAndFluid, 400, ci, cj);
  const unsigned char* fluidThere = Pixel(picture, 400, ci, cj);
  std::printf("sphere pixel (%d, %d): alone %d %d %d, with fluid %d %d %d, fluid alone %d %d %d; "
              "stopped spans %lld\n",
    ci, cj, a[0], a[1], a[2], b[0], b[1], b[2], fluidThere[0], fluidThere[1], fluidThere[2],
    counter("stopped_spans"));
  check(std::equal(a, a + 3, b) && !std::equal(fluidThere, fluidThere + 3, b) &&
      stats->GetEffect("opaque_depth") && counter("stopped_spans") > 0,
    "translucent fluid behind an opaque sphere: the sphere's pixels unchanged");
  mapper->TranslucencyOff();
  const auto opaqueFluid = render();
  const unsigned char* o = Pixel(opaqueFluid, 400, ci, cj);
  check(std::equal(a, a + 3, o) && counter("translucent_pixels") == 0,
    "opaque fluid behind the sphere: the depth test keeps the sphere");
  mapper->TranslucencyOn();
  ren->RemoveActor(actor);

  // The baseline: refraction, smoothing and AO together.
  mapper->SetRefractiveIndex(1.33);
  mapper->SetSmoothingRadius(0.03);
  mapper->AmbientOcclusionOn();
  render();
  check(rmtest::CompareWithBaseline(win, argc, argv) == EXIT_SUCCESS, "matches the baseline");

  for (const double scale : { 1.0, 1e-3, 1e3 })
  {
    check(CheckBeerLambert(scale), "Beer-Lambert per particle radius at this scale");
  }
  check(CheckColorBy(), "coloured by a point array through a lookup table");
  return ok ? EXIT_SUCCESS : EXIT_FAILURE;
}
