// Draws a kernel's Frame (premultiplied RGBA + window depth) into the current OpenGL
// framebuffer over the renderer's (tiled) viewport with one full-screen quad.
//
// Opaque mode: pixels with alpha > 0 are written with their depth (gl_FragDepth) under the
// normal depth test, so the frame hides and is hidden by ordinary geometry.
// Blend mode: the frame is composited over what is drawn, premultiplied
// (src + (1 - src.a) dst), without writing depth; a volume kernel has already stopped its
// rays at the opaque depth (see vtkRayMapperRenderHelpers::ReadOpaqueDepth).
// The frame goes to the GPU as float textures (colour; depth in opaque mode only) that keep
// their storage from one frame to the next while the size and the window stay the same.
// Every mapper draws through here, so this is where the frame validation of
// vtkRayMapperStatistics::ValidateFrames looks at what is drawn.
#ifndef vtkRayMapperFrameDrawer_h
#define vtkRayMapperFrameDrawer_h

#include "Mappers/Common/Frame.h"
#include "RayMappersMappersModule.h" // for export macro
#include "Mappers/Common/RenderStatistics.h"

#include <memory>

class vtkRenderer;
class vtkWindow;

class RAYMAPPERSMAPPERS_EXPORT vtkRayMapperFrameDrawer
{
public:
  enum class Mode
  {
    OpaqueWithDepth,
    BlendPremultiplied
  };

  vtkRayMapperFrameDrawer();
  ~vtkRayMapperFrameDrawer();
  vtkRayMapperFrameDrawer(const vtkRayMapperFrameDrawer&) = delete;
  vtkRayMapperFrameDrawer& operator=(const vtkRayMapperFrameDrawer&) = delete;

  /// The frame must have the size of the renderer's tiled viewport. With `validate` (the
  /// mapper's vtkRayMapperStatistics::ValidateFrames) the frame is checked first
  /// (FrameValidation.h) into the counters frame_nonfinite_values and
  /// frame_out_of_range_values and the effect frame_validation of `stats`; without, it is
  /// not looked at.
  void Draw(vtkRenderer* ren,
    const raymappers::Frame& frame,
    Mode mode,
    bool validate,
    raymappers::RenderStatistics& stats);
  void ReleaseGraphicsResources(vtkWindow* win);

private:
  struct GL;
  std::unique_ptr<GL> Impl;
};

#endif
