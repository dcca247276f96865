#include "vtkRayMapperFrameDrawer.h"

#include "Mappers/Common/FrameValidation.h"

#include "vtkOpenGLQuadHelper.h"
#include "vtkOpenGLRenderUtilities.h"
#include "vtkOpenGLRenderWindow.h"
#include "vtkOpenGLShaderCache.h"
#include "vtkOpenGLState.h"
#include "vtkRenderer.h"
#include "vtkShaderProgram.h"
#include "vtkTextureObject.h"
#include "vtk_glew.h"

#include <memory>
#include <string>

namespace
{
// texCoord spans the viewport; with NEAREST sampling each fragment reads its own texel.
// Opaque mode (WRITE_DEPTH defined) writes the frame's depth; blend mode reads no depth
// texture at all.
const char* const FrameFragmentShaderBody = R"(
in vec2 texCoord;
uniform sampler2D colorTexture;
#ifdef WRITE_DEPTH
uniform sampler2D depthTexture;
#endif
//VTK::Output::Dec
void main()
{
  vec4 c = texture(colorTexture, texCoord);
  if (c.a <= 0.0)
  {
    discard;
  }
  gl_FragData[0] = c;
#ifdef WRITE_DEPTH
  gl_FragDepth = texture(depthTexture, texCoord).r;
#endif
}
)";

std::string FrameFragmentShader(bool writeDepth)
{
  return std::string("//VTK::System::Dec\n") + (writeDepth ? "#define WRITE_DEPTH\n" : "") +
    FrameFragmentShaderBody;
}

// Uploads w x h texels of `components` floats: into the texture's storage when it already
// has that shape in this window (no reallocation of the driver's copy each frame), else as
// new storage.
void Upload(vtkTextureObject* tex, bool sameWindow, int w, int h, int components,
  const float* data)
{
  if (sameWindow && tex->GetHandle() != 0 && static_cast<int>(tex->GetWidth()) == w &&
    static_cast<int>(tex->GetHeight()) == h && tex->GetComponents() == components &&
    tex->GetVTKDataType() == VTK_FLOAT)
  {
    tex->Bind();
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, w, h, tex->GetFormat(VTK_FLOAT, components, false),
      GL_FLOAT, data);
    return;
  }
  tex->Create2DFromRaw(w, h, components, VTK_FLOAT, const_cast<float*>(data));
}
}

struct vtkRayMapperFrameDrawer::GL
{
  vtkNew<vtkTextureObject> Color;
  vtkNew<vtkTextureObject> Depth;
  std::unique_ptr<vtkOpenGLQuadHelper> OpaqueQuad;
  std::unique_ptr<vtkOpenGLQuadHelper> BlendQuad;
  // The windows the textures were last uploaded in.
  const vtkOpenGLRenderWindow* ColorWindow = nullptr;
  const vtkOpenGLRenderWindow* DepthWindow = nullptr;
};

vtkRayMapperFrameDrawer::vtkRayMapperFrameDrawer()
  : Impl(new GL)
{
}

vtkRayMapperFrameDrawer::~vtkRayMapperFrameDrawer() = default;

void vtkRayMapperFrameDrawer::ReleaseGraphicsResources(vtkWindow* win)
{
  Impl->Color->ReleaseGraphicsResources(win);
  Impl->Depth->ReleaseGraphicsResources(win);
  for (auto* quad : { &Impl->OpaqueQuad, &Impl->BlendQuad })
  {
    if (*quad)
    {
      (*quad)->ReleaseGraphicsResources(win);
      quad->reset();
    }
  }
}

void vtkRayMapperFrameDrawer::Draw(vtkRenderer* ren,
  const raymappers::Frame& frame,
  Mode mode,
  bool validate,
  raymappers::RenderStatistics& stats)
{
  stats.setEffect("frame_validation", validate);
  if (validate)
  {
    const raymappers::FrameValidation check = raymappers::validateFrame(frame);
    stats.addCounter("frame_nonfinite_values", check.nonFinite);
    stats.addCounter("frame_out_of_range_values", check.outOfRange);
  }
  auto* renWin = vtkOpenGLRenderWindow::SafeDownCast(ren->GetRenderWindow());
  if (!renWin || frame.width <= 0 || frame.height <= 0)
  {
    return;
  }
  vtkOpenGLState* ostate = renWin->GetState();

  const bool opaque = mode == Mode::OpaqueWithDepth;
  for (vtkTextureObject* tex : { Impl->Color.Get(), Impl->Depth.Get() })
  {
    tex->SetContext(renWin);
    tex->SetMinificationFilter(vtkTextureObject::Nearest);
    tex->SetMagnificationFilter(vtkTextureObject::Nearest);
    tex->SetWrapS(vtkTextureObject::ClampToEdge);
    tex->SetWrapT(vtkTextureObject::ClampToEdge);
  }
  Upload(Impl->Color, Impl->ColorWindow == renWin, frame.width, frame.height, 4,
    frame.rgba.data());
  Impl->ColorWindow = renWin;
  if (opaque)
  {
    Upload(Impl->Depth, Impl->DepthWindow == renWin, frame.width, frame.height, 1,
      frame.depth.data());
    Impl->DepthWindow = renWin;
  }

  std::unique_ptr<vtkOpenGLQuadHelper>& quad = opaque ? Impl->OpaqueQuad : Impl->BlendQuad;
  if (!quad)
  {
    quad.reset(new vtkOpenGLQuadHelper(renWin,
      vtkOpenGLRenderUtilities::GetFullScreenQuadVertexShader().c_str(),
      FrameFragmentShader(opaque).c_str(), ""));
  }
  else
  {
    renWin->GetShaderCache()->ReadyShaderProgram(quad->Program);
  }
  if (!quad->Program || !quad->Program->GetCompiled())
  {
    vtkGenericWarningMacro("RayMappers: the frame shader failed to compile; nothing drawn.");
    return;
  }

  vtkOpenGLState::ScopedglEnableDisable depthTest(ostate, GL_DEPTH_TEST);
  vtkOpenGLState::ScopedglEnableDisable blend(ostate, GL_BLEND);
  vtkOpenGLState::ScopedglDepthMask depthMask(ostate);
  vtkOpenGLState::ScopedglDepthFunc depthFunc(ostate);
  vtkOpenGLState::ScopedglBlendFuncSeparate blendFunc(ostate);
  // The quad covers the renderer's tiled viewport, set here: after the renderer's passes
  // (a translucent frame drawn at its EndEvent) the viewport may be the whole window's.
  vtkOpenGLState::ScopedglViewport viewport(ostate);
  vtkOpenGLState::ScopedglScissor scissor(ostate);
  int size[2], origin[2];
  ren->GetTiledSizeAndOrigin(&size[0], &size[1], &origin[0], &origin[1]);
  ostate->vtkglViewport(origin[0], origin[1], size[0], size[1]);
  ostate->vtkglScissor(origin[0], origin[1], size[0], size[1]);
  if (opaque)
  {
    ostate->vtkglEnable(GL_DEPTH_TEST);
    ostate->vtkglDepthFunc(GL_LEQUAL);
    ostate->vtkglDepthMask(GL_TRUE);
    ostate->vtkglDisable(GL_BLEND);
  }
  else
  {
    ostate->vtkglDisable(GL_DEPTH_TEST);
    ostate->vtkglDepthMask(GL_FALSE);
    ostate->vtkglEnable(GL_BLEND);
    ostate->vtkglBlendFuncSeparate(GL_ONE, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
  }

  Impl->Color->Activate();
  quad->Program->SetUniformi("colorTexture", Impl->Color->GetTextureUnit());
  if (opaque)
  {
    Impl->Depth->Activate();
    quad->Program->SetUniformi("depthTexture", Impl->Depth->GetTextureUnit());
  }
  quad->Render();
  Impl->Color->Deactivate();
  if (opaque)
  {
    Impl->Depth->Deactivate();
  }
}
