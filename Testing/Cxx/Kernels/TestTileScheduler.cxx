// Every pixel is visited once, whatever the tile size.
#include "Mappers/Common/TileScheduler.h"

#include <gtest/gtest.h>

#include <atomic>
#include <vector>

TEST(TileScheduler, EveryPixelOnceForAnyTileSize)
{
  for (int w : { 1, 17, 64, 129 })
  {
    for (int h : { 1, 9, 64 })
    {
      for (int ts : { 1, 4, 7, 32, 1000 })
      {
        std::vector<std::atomic<int>> visits(static_cast<std::size_t>(w * h));
        raymappers::forEachTile(w,
          h,
          ts,
          [&](const raymappers::Tile& t)
          {
            EXPECT_LE(t.x1 - t.x0, ts);
            EXPECT_LE(t.y1 - t.y0, ts);
            for (int j = t.y0; j < t.y1; ++j)
            {
              for (int i = t.x0; i < t.x1; ++i)
              {
                ++visits[static_cast<std::size_t>(j * w + i)];
              }
            }
          });
        for (const auto& v : visits)
        {
          ASSERT_EQ(v.load(), 1) << w << "x" << h << " tile " << ts;
        }
      }
    }
  }
}

TEST(TileScheduler, EmptyGridRunsNothing)
{
  int calls = 0;
  raymappers::forEachTile(0, 10, 8, [&](const raymappers::Tile&) { ++calls; });
  raymappers::forEachTile(10, -1, 8, [&](const raymappers::Tile&) { ++calls; });
  EXPECT_EQ(calls, 0);
}
