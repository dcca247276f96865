// Reordering a set's arrays into the order of an acceleration structure (cells, leaves),
// element i taking element order[i]'s `width` values: gathered in parallel into a LargeBuffer
// and copied back, so that the array keeps its memory (faulted in once and reused by every
// later build of the same size) and the build's peak holds one array twice.
#ifndef RayMappers_PermuteInPlace_h
#define RayMappers_PermuteInPlace_h

#include "Mappers/Common/LargeBuffer.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace raymappers
{

template<typename T>
void permuteInPlace(std::vector<T>& values, const std::uint32_t* order, std::size_t width = 1)
{
  if (values.empty() || width == 0)
  {
    return;
  }
  const std::size_t n = values.size() / width;
  LargeBuffer<T> sorted(values.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096),
    [&](const tbb::blocked_range<std::size_t>& range)
    {
      for (std::size_t i = range.begin(); i != range.end(); ++i)
      {
        const std::size_t from = order[i];
        for (std::size_t w = 0; w < width; ++w)
        {
          sorted[i * width + w] = values[from * width + w];
        }
      }
    });
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, values.size(), 65536),
    [&](const tbb::blocked_range<std::size_t>& range)
    {
      std::copy(sorted.data() + range.begin(), sorted.data() + range.end(),
        values.data() + range.begin());
    });
}

} // namespace raymappers

#endif
