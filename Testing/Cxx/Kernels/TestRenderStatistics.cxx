#include "Mappers/Common/RenderStatistics.h"

#include <gtest/gtest.h>

using raymappers::RenderStatistics;

TEST(RenderStatistics, CountersPhasesAndEffects)
{
  RenderStatistics s;
  s.declareCounter("shadow_rays");
  s.addCounter("rays", 5);
  s.addCounter("rays", 7);
  s.addPhase("trace", 1.5);
  s.addPhase("trace", 2.0);
  s.addPhase("draw", 0.5);
  s.setEffect("shading", true);
  s.setEffect("shadows", false);
  EXPECT_EQ(s.counter("rays"), 12);
  EXPECT_EQ(s.counter("shadow_rays"), 0);
  EXPECT_EQ(s.counter("unknown"), 0);
  EXPECT_DOUBLE_EQ(s.phase("trace"), 3.5);
  EXPECT_DOUBLE_EQ(s.totalMs(), 4.0);
  EXPECT_TRUE(s.effect("shading"));
  EXPECT_FALSE(s.effect("shadows"));
  EXPECT_NE(s.summary().find("counter shadow_rays 0"), std::string::npos);
  EXPECT_NE(s.summary().find("effect shadows off"), std::string::npos);
  s.clear();
  EXPECT_EQ(s.counters().size(), 0u);
}
