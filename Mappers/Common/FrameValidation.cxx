#include "Mappers/Common/FrameValidation.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <cmath>
#include <cstddef>

namespace raymappers
{

namespace
{
FrameValidation validatePixels(const Frame& frame, std::size_t begin, std::size_t end)
{
  FrameValidation v;
  const bool haveDepth = frame.depth.size() * 4 == frame.rgba.size();
  for (std::size_t p = begin; p < end; ++p)
  {
    const float* c = &frame.rgba[4 * p];
    const float a = c[3];
    const bool alphaFinite = std::isfinite(a);
    v.nonFinite += !alphaFinite;
    v.outOfRange += alphaFinite && (a < 0.f || a > 1.f);
    for (int k = 0; k < 3; ++k)
    {
      if (!std::isfinite(c[k]))
      {
        ++v.nonFinite;
      }
      else if (c[k] < -FrameColorTolerance ||
        (alphaFinite && c[k] > a + FrameColorTolerance))
      {
        ++v.outOfRange;
      }
    }
    if (haveDepth)
    {
      const float d = frame.depth[p];
      v.nonFinite += !std::isfinite(d);
      v.outOfRange += std::isfinite(d) && (d < 0.f || d > 1.f);
    }
  }
  return v;
}
}

FrameValidation validateFrame(const Frame& frame)
{
  const std::size_t pixels = frame.rgba.size() / 4;
  return tbb::parallel_reduce(
    tbb::blocked_range<std::size_t>(0, pixels, 16384),
    FrameValidation(),
    [&](const tbb::blocked_range<std::size_t>& r, FrameValidation v)
    {
      const FrameValidation part = validatePixels(frame, r.begin(), r.end());
      v.nonFinite += part.nonFinite;
      v.outOfRange += part.outOfRange;
      return v;
    },
    [](FrameValidation a, const FrameValidation& b)
    {
      a.nonFinite += b.nonFinite;
      a.outOfRange += b.outOfRange;
      return a;
    });
}

} // namespace raymappers
