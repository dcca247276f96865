// What the distributed-rendering kernel tests share: a kd-tree cut of space into three
// regions, listed in visibility order for an eye at x > xCut and z > zCut, and the front to
// back blending of the regions' premultiplied images (what IceT's ordered compositing does).
#ifndef RayMappers_Test_RegionFixtures_h
#define RayMappers_Test_RegionFixtures_h

#include "Mappers/Common/Frame.h"
#include "Mappers/Common/RegionBox.h"

#include <array>

namespace raymappers::test
{

/// x = xCut first, then z = zCut on the eye's side: (x >= xCut, z >= zCut),
/// (x >= xCut, z < zCut), (x < xCut).
inline std::array<RegionBox, 3> kdCutFrontToBack(double xCut, double zCut)
{
  std::array<RegionBox, 3> regions;
  regions[0].lo[0] = regions[1].lo[0] = xCut;
  regions[0].lo[2] = zCut;
  regions[1].hi[2] = zCut;
  regions[2].hi[0] = xCut;
  return regions;
}

/// composite = composite over part: part is behind what has been blended so far.
inline void blendBehind(Frame& composite, const Frame& part)
{
  for (std::size_t i = 0; i < composite.rgba.size(); i += 4)
  {
    const float t = 1.f - composite.rgba[i + 3];
    for (int c = 0; c < 4; ++c)
    {
      composite.rgba[i + c] += t * part.rgba[i + c];
    }
  }
}

} // namespace raymappers::test

#endif
