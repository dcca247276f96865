// vtkZSweepVolumeMapper against the brute-force unstructured reference
// (Testing/Cxx/Kernels/UnstructuredReference.h: every tetrahedron clipped by each pixel's ray
// in double, the segments sorted and integrated piece by piece between the transfer
// function's nodes, sharing no code with the sweep), in a real render window with the rays of
// Testing/References' camera, on disk_out_ref.ex2 cut into 44,832 tetrahedra (the point
// field Temp): the Exact integrator (the default), Farias's and the midpoint rule.
//
// Measured on this machine (160 x 120, levels of 255; differing: beyond 2 levels): Exact rmse
// 0.40, max error 1, none (the 8-bit blend over the background rounds once more than the
// reference); Farias rmse 4.96, max error 46, 15.0% (its approximation of the integral); the
// midpoint rule rmse 0.41, max error 2, none. The bounds are 1.5 times these (the fraction
// at least 0.05%, the max error at least 2).
//
// usage: TestZSweepVolumeMapperReference -D <Data dir>
#include "ReferenceFromVTK.h"
#include "RenderingTestHelpers.h"
#include "UnstructuredReference.h"
#include "vtkZSweepVolumeMapper.h"

#include "vtkColorTransferFunction.h"
#include "vtkCompositeDataIterator.h"
#include "vtkDataSetTriangleFilter.h"
#include "vtkExodusIIReader.h"
#include "vtkIdList.h"
#include "vtkMultiBlockDataSet.h"
#include "vtkPiecewiseFunction.h"
#include "vtkTestUtilities.h"
#include "vtkUnstructuredGrid.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"

#include <tbb/parallel_for.h>

#include <algorithm>

namespace ref = raymappers::reference;
using raymappers::Vec3d;

namespace
{
vtkSmartPointer<vtkUnstructuredGrid> ReadTetrahedra(const char* file)
{
  vtkNew<vtkExodusIIReader> reader;
  reader->SetFileName(file);
  reader->UpdateInformation();
  reader->SetAllArrayStatus(vtkExodusIIReader::NODAL, 1);
  reader->SetAllArrayStatus(vtkExodusIIReader::ELEM_BLOCK, 1);
  reader->Update();
  auto* blocks = vtkMultiBlockDataSet::SafeDownCast(reader->GetOutputDataObject(0));
  vtkSmartPointer<vtkCompositeDataIterator> it;
  it.TakeReference(blocks->NewIterator());
  it->InitTraversal();
  vtkNew<vtkDataSetTriangleFilter> tets;
  tets->SetInputData(vtkDataSet::SafeDownCast(it->GetCurrentDataObject()));
  tets->Update();
  return tets->GetOutput();
}

// The reference's transfer function: VTK's nodes of both functions, colour and opacity at
// each (the model linear between them).
raymappers::test::RefTransferFunction NodesOf(vtkVolumeProperty* property)
{
  vtkColorTransferFunction* color = property->GetRGBTransferFunction();
  vtkPiecewiseFunction* opacity = property->GetScalarOpacity();
  std::vector<double> xs;
  double node[6];
  for (int i = 0; i < color->GetSize(); ++i)
  {
    color->GetNodeValue(i, node);
    xs.push_back(node[0]);
  }
  for (int i = 0; i < opacity->GetSize(); ++i)
  {
    opacity->GetNodeValue(i, node);
    xs.push_back(node[0]);
  }
  std::sort(xs.begin(), xs.end());
  xs.erase(std::unique(xs.begin(), xs.end()), xs.end());
  raymappers::test::RefTransferFunction tf;
  for (const double x : xs)
  {
    double rgb[3];
    color->GetColor(x, rgb);
    tf.s.push_back(x);
    tf.rgb.insert(tf.rgb.end(), rgb, rgb + 3);
    tf.alpha.push_back(opacity->GetValue(x));
  }
  tf.unitDistance = property->GetScalarOpacityUnitDistance();
  return tf;
}

raymappers::test::RGBImage Reference(vtkUnstructuredGrid* grid,
  vtkVolumeProperty* property,
  const ref::ReferenceCamera& cam,
  const ref::Point& background)
{
  std::vector<raymappers::test::RefTetra> tets;
  vtkDataArray* temp = grid->GetPointData()->GetArray("Temp");
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c)
  {
    grid->GetCellPoints(c, ids);
    raymappers::test::RefTetra t;
    for (int k = 0; k < 4; ++k)
    {
      double p[3];
      grid->GetPoint(ids->GetId(k), p);
      t.p[static_cast<std::size_t>(k)] = Vec3d(p[0], p[1], p[2]);
      t.s[static_cast<std::size_t>(k)] = temp->GetTuple1(ids->GetId(k));
    }
    tets.push_back(t);
  }
  const raymappers::test::ReferenceTetraGrid cells(tets);
  const raymappers::test::RefTransferFunction tf = NodesOf(property);
  ref::ReferenceImage image(cam.width(), cam.height());
  tbb::parallel_for(0,
    cam.height(),
    [&](int j)
    {
      std::vector<std::size_t> candidates;
      for (int i = 0; i < cam.width(); ++i)
      {
        const ref::PixelRay ray = cam.ray(i, j);
        const Vec3d o(ray.origin.x, ray.origin.y, ray.origin.z);
        const Vec3d d(ray.direction.x, ray.direction.y, ray.direction.z);
        cells.candidates(o, d, 0.0, candidates);
        image.at(i, j) =
          raymappers::test::traceReference(tets, false, tf, o, d, 0.0, &candidates, 64);
      }
    });
  return { image.width, image.height, image.over(background) };
}
}

int TestZSweepVolumeMapperReference(int argc, char* argv[])
{
  char* file = vtkTestUtilities::ExpandDataFileName(argc, argv, "disk_out_ref.ex2");
  vtkSmartPointer<vtkUnstructuredGrid> grid = ReadTetrahedra(file);
  delete[] file;
  RM_CHECK(grid->GetNumberOfCells() > 40000 && grid->GetPointData()->GetArray("Temp"));
  double range[2];
  grid->GetPointData()->GetArray("Temp")->GetRange(range);
  const double mid = 0.5 * (range[0] + range[1]);

  vtkNew<vtkColorTransferFunction> color;
  color->AddRGBPoint(range[0], 0.23, 0.30, 0.75);
  color->AddRGBPoint(mid, 0.87, 0.87, 0.87);
  color->AddRGBPoint(range[1], 0.71, 0.02, 0.15);
  vtkNew<vtkPiecewiseFunction> opacity;
  opacity->AddPoint(range[0], 0.02);
  opacity->AddPoint(mid, 0.15);
  opacity->AddPoint(range[1], 0.9);
  vtkNew<vtkVolumeProperty> property;
  property->SetColor(color);
  property->SetScalarOpacity(opacity);
  property->SetScalarOpacityUnitDistance(1.0);
  vtkNew<vtkZSweepVolumeMapper> mapper;
  mapper->SetInputData(grid);
  mapper->SetScalarModeToUsePointFieldData();
  mapper->SelectScalarArray("Temp");
  vtkNew<vtkVolume> volume;
  volume->SetMapper(mapper);
  volume->SetProperty(property);
  vtkNew<vtkRenderer> ren;
  const ref::Point background{ 1, 1, 1 };
  ren->SetBackground(background.x, background.y, background.z);
  ren->AddVolume(volume);
  vtkNew<vtkRenderWindow> win;
  win->SetSize(160, 120);
  win->AddRenderer(ren);
  ren->ResetCamera();
  vtkCamera* camera = ren->GetActiveCamera();
  camera->Azimuth(40);
  camera->Elevation(25);
  camera->Dolly(1.6);
  ren->ResetCameraClippingRange();
  win->Render();
  const raymappers::test::RGBImage want = Reference(grid, property, ref::cameraOf(ren), background);

  struct Setting
  {
    const char* name;
    int integrator;
    raymappers::test::ImageThresholds bound;
  };
  const Setting settings[] = {
    { "Exact (the default)", VTK_ZSWEEP_INTEGRATOR_EXACT, { 0.61, 0.0005, 2, 2 } },
    { "Farias", VTK_ZSWEEP_INTEGRATOR_FARIAS, { 7.5, 0.225, 2, 69 } },
    { "midpoint", VTK_ZSWEEP_INTEGRATOR_MIDPOINT, { 0.62, 0.0005, 2, 3 } },
  };
  bool ok = true;
  for (const Setting& s : settings)
  {
    mapper->SetIntegrator(s.integrator);
    win->Render();
    ok = rmtest::CheckAgainstReference(win, want, s.bound, s.name) && ok;
  }
  return ok ? EXIT_SUCCESS : EXIT_FAILURE;
}
