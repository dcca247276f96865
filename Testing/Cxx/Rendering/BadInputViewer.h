// The scene of the mappers' bad-input tests (Test*BadInput.cxx): one mapper in a square
// window, the camera looking at the origin from a given eye, the mapper's warnings and
// errors counted (BadInputLog), and Render() reading back the picture with the clipping
// range of a fixed cube, so bad points cannot move it.
#ifndef RayMappers_BadInputViewer_h
#define RayMappers_BadInputViewer_h

#include "RenderingTestHelpers.h"

#include "vtkVolume.h"
#include "vtkVolumeProperty.h"

namespace rmtest
{

template<typename MapperT, typename DataT>
struct BadInputViewer
{
  vtkNew<MapperT> Mapper;
  vtkNew<vtkRenderer> Ren;
  vtkNew<vtkRenderWindow> Win;
  EventCounter Events;
  BadInputLog Log{ Events, Mapper->GetStatistics() };
  /// Half the side of the cube centred on the origin that sets the clipping range.
  double ClipHalfSide = 2;

  /// The window of size x size pixels, the eye at (x, y, z) looking at the origin; the
  /// mapper's messages counted from here on.
  void Open(int size, double x, double y, double z)
  {
    Win->SetSize(size, size);
    Win->AddRenderer(Ren);
    Ren->GetActiveCamera()->SetPosition(x, y, z);
    Ren->GetActiveCamera()->SetFocalPoint(0, 0, 0);
    Events.Observe(Mapper);
  }
  raymappers::test::RGBImage Show(DataT* data)
  {
    Mapper->SetInputData(data);
    return Render();
  }
  raymappers::test::RGBImage Render()
  {
    const double h = ClipHalfSide;
    Ren->ResetCameraClippingRange(-h, h, -h, h, -h, h);
    Win->Render();
    return raymappers::test::fromWindow(Win);
  }
};

/// The volume mappers' scene: the mapper in a vtkVolume with its own property.
template<typename MapperT, typename DataT>
struct BadInputVolumeViewer : BadInputViewer<MapperT, DataT>
{
  vtkNew<vtkVolumeProperty> Property;
  vtkNew<vtkVolume> Volume;
  BadInputVolumeViewer()
  {
    Volume->SetMapper(this->Mapper);
    Volume->SetProperty(Property);
    this->Ren->AddVolume(Volume);
  }
};

}

#endif
