// The image a kernel produces: premultiplied RGBA and window depth per pixel, row 0 at the
// bottom (OpenGL order). An empty pixel is (0,0,0,0) with depth 1 (the far plane).
#ifndef RayMappers_Frame_h
#define RayMappers_Frame_h

#include <cstddef>
#include <cstdint>
#include <vector>

namespace raymappers
{

struct Frame
{
  int width = 0;
  int height = 0;
  std::vector<float> rgba;  // 4 floats per pixel, premultiplied by alpha
  std::vector<float> depth; // window depth in [0, 1]

  void resize(int w, int h)
  {
    width = w;
    height = h;
    const std::size_t n = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
    rgba.assign(4 * n, 0.f);
    depth.assign(n, 1.f);
  }
  /// The same size without clearing when it is unchanged, for a kernel that writes every
  /// pixel's colour each frame and leaves the depth as it was (resized storage is empty).
  void reshape(int w, int h)
  {
    const std::size_t n = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
    if (w != width || h != height || rgba.size() != 4 * n || depth.size() != n)
    {
      resize(w, h);
    }
  }
  std::size_t index(int i, int j) const
  {
    return static_cast<std::size_t>(j) * static_cast<std::size_t>(width) +
           static_cast<std::size_t>(i);
  }
};

/// What each pixel of a hardware-selection pass shows: 0 for nothing, else the id + 1 of the
/// element in front (a point id for spheres), with the window depth of that element (1 for
/// nothing); row 0 at the bottom, like Frame.
struct IdFrame
{
  int width = 0;
  int height = 0;
  std::vector<std::uint32_t> ids;
  std::vector<float> depth;

  void resize(int w, int h)
  {
    width = w;
    height = h;
    const std::size_t n = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
    ids.assign(n, 0u);
    depth.assign(n, 1.f);
  }
};

} // namespace raymappers

#endif
