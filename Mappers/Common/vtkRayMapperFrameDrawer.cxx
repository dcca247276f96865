#include "vtkRayMapperFrameDrawer.h"

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

namespace
{
// texCoord spans the viewport; with NEAREST sampling each fragment reads its own texel.
const char* const FrameFragmentShader = R"(//VTK::System::Dec
in vec2 texCoord;
uniform sampler2D colorTexture;
uniform sampler2D depthTexture;
uniform int writeDepth;
//VTK::Output::Dec
void main()
{
  vec4 c = texture(colorTexture, texCoord);
  if (c.a <= 0.0)
  {
    discard;
  }
  gl_FragData[0] = c;
  gl_FragDepth = writeDepth != 0 ? texture(depthTexture, texCoord).r : gl_FragCoord.z;
}
)";
}

struct vtkRayMapperFrameDrawer::GL
{
  vtkNew<vtkTextureObject> Color;
  vtkNew<vtkTextureObject> Depth;
  std::unique_ptr<vtkOpenGLQuadHelper> Quad;
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
  if (Impl->Quad)
  {
    Impl->Quad->ReleaseGraphicsResources(win);
    Impl->Quad.reset();
  }
}

void vtkRayMapperFrameDrawer::Draw(vtkRenderer* ren, const raymappers::Frame& frame, Mode mode)
{
  auto* renWin = vtkOpenGLRenderWindow::SafeDownCast(ren->GetRenderWindow());
  if (!renWin || frame.width <= 0 || frame.height <= 0)
  {
    return;
  }
  vtkOpenGLState* ostate = renWin->GetState();

  for (vtkTextureObject* tex : { Impl->Color.Get(), Impl->Depth.Get() })
  {
    tex->SetContext(renWin);
    tex->SetMinificationFilter(vtkTextureObject::Nearest);
    tex->SetMagnificationFilter(vtkTextureObject::Nearest);
    tex->SetWrapS(vtkTextureObject::ClampToEdge);
    tex->SetWrapT(vtkTextureObject::ClampToEdge);
  }
  Impl->Color->Create2DFromRaw(
    frame.width, frame.height, 4, VTK_FLOAT, const_cast<float*>(frame.rgba.data()));
  Impl->Depth->Create2DFromRaw(
    frame.width, frame.height, 1, VTK_FLOAT, const_cast<float*>(frame.depth.data()));

  if (!Impl->Quad)
  {
    Impl->Quad.reset(new vtkOpenGLQuadHelper(renWin,
      vtkOpenGLRenderUtilities::GetFullScreenQuadVertexShader().c_str(),
      FrameFragmentShader,
      ""));
  }
  else
  {
    renWin->GetShaderCache()->ReadyShaderProgram(Impl->Quad->Program);
  }
  if (!Impl->Quad->Program || !Impl->Quad->Program->GetCompiled())
  {
    vtkGenericWarningMacro("RayMappers: the frame shader failed to compile; nothing drawn.");
    return;
  }

  const bool opaque = mode == Mode::OpaqueWithDepth;
  vtkOpenGLState::ScopedglEnableDisable depthTest(ostate, GL_DEPTH_TEST);
  vtkOpenGLState::ScopedglEnableDisable blend(ostate, GL_BLEND);
  vtkOpenGLState::ScopedglDepthMask depthMask(ostate);
  vtkOpenGLState::ScopedglDepthFunc depthFunc(ostate);
  vtkOpenGLState::ScopedglBlendFuncSeparate blendFunc(ostate);
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
  Impl->Depth->Activate();
  Impl->Quad->Program->SetUniformi("colorTexture", Impl->Color->GetTextureUnit());
  Impl->Quad->Program->SetUniformi("depthTexture", Impl->Depth->GetTextureUnit());
  Impl->Quad->Program->SetUniformi("writeDepth", opaque ? 1 : 0);
  Impl->Quad->Render();
  Impl->Color->Deactivate();
  Impl->Depth->Deactivate();
}
