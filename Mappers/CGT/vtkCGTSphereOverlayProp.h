/**
 * @class   vtkCGTSphereOverlayProp
 * @brief   draws a vtkCGTSphereMapper's translucent spheres in the renderer's overlay step
 *
 * Translucent spheres are drawn when the renderer's render ends (vtkCGTSphereMapper): after
 * every pass, blended over all the renderer drew. A compositing render pass reads the image
 * before that, inside the render (vtkIceTCompositePass under MPI reads every process's
 * image right after the geometry): the spheres would miss the composite, and be blended on
 * the display process only, over the composited picture. This prop, added to the renderer
 * with the actor, draws them in the renderer's overlay step instead (after the opaque,
 * translucent and volumetric steps, before the image is read): the same picture with one
 * process, and each process's spheres in its own image with several. It has no bounds and
 * draws nothing else.
 */
#ifndef vtkCGTSphereOverlayProp_h
#define vtkCGTSphereOverlayProp_h

#include "RayMappersMappersModule.h"
#include "vtkProp.h"
#include "vtkWeakPointer.h"

class vtkCGTSphereMapper;

class RAYMAPPERSMAPPERS_EXPORT vtkCGTSphereOverlayProp : public vtkProp
{
public:
  static vtkCGTSphereOverlayProp* New();
  vtkTypeMacro(vtkCGTSphereOverlayProp, vtkProp);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /**
   * The mapper whose deferred spheres this prop draws (not reference counted).
   */
  void SetMapper(vtkCGTSphereMapper* mapper);
  vtkCGTSphereMapper* GetMapper();

  /**
   * Draws the mapper's waiting translucent spheres (vtkCGTSphereMapper::DrawDeferredSpheres).
   */
  int RenderOverlay(vtkViewport* viewport) override;

protected:
  vtkCGTSphereOverlayProp();
  ~vtkCGTSphereOverlayProp() override;

private:
  vtkCGTSphereOverlayProp(const vtkCGTSphereOverlayProp&) = delete;
  void operator=(const vtkCGTSphereOverlayProp&) = delete;

  vtkWeakPointer<vtkCGTSphereMapper> Mapper;
};

#endif
