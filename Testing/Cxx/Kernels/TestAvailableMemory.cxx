// availableMemoryBytes (Mappers/Common/AvailableMemory.h) against the system's own figures,
// read here through other calls (sysinfo, getrlimit), and the automatic budget that SPH Fluid
// takes from it (SpanVoxelizer.h).
#include "Mappers/Common/AvailableMemory.h"
#include "Mappers/SPH/SpanVoxelizer.h"

#include <gtest/gtest.h>

#include <sys/resource.h>
#include <sys/sysinfo.h>
#include <unistd.h>

#include <cstddef>
#include <cstdio>
#include <string>

using raymappers::availableMemoryBytes;

namespace
{
/// The address space in use, from /proc/self/statm (pages), not /proc/self/status.
std::size_t addressSpaceInUse()
{
  unsigned long pages = 0;
  std::FILE* f = std::fopen("/proc/self/statm", "r");
  if (f)
  {
    if (std::fscanf(f, "%lu", &pages) != 1)
    {
      pages = 0;
    }
    std::fclose(f);
  }
  return static_cast<std::size_t>(pages) * static_cast<std::size_t>(sysconf(_SC_PAGESIZE));
}
} // namespace

TEST(AvailableMemory, IsPositiveAndWithinThePhysicalMemory)
{
  struct sysinfo info{};
  ASSERT_EQ(sysinfo(&info), 0);
  const std::size_t total = static_cast<std::size_t>(info.totalram) * info.mem_unit;
  const std::size_t available = availableMemoryBytes();
  EXPECT_GT(available, 0u);
  EXPECT_LE(available, total);
}

TEST(AvailableMemory, AnAddressSpaceLimitBindsAndTheAutomaticBudgetKeepsItsFloor)
{
  rlimit saved{};
  ASSERT_EQ(getrlimit(RLIMIT_AS, &saved), 0);
  const std::size_t headroom = std::size_t(300) << 20;
  const std::size_t cap = addressSpaceInUse() + headroom;
  if (saved.rlim_max != RLIM_INFINITY && saved.rlim_max < cap)
  {
    GTEST_SKIP() << "the hard address-space limit is below the test's";
  }
  rlimit lowered = saved;
  lowered.rlim_cur = cap;
  ASSERT_EQ(setrlimit(RLIMIT_AS, &lowered), 0);
  const std::size_t available = availableMemoryBytes();
  const std::size_t budget = raymappers::automaticMemoryBudget();
  ASSERT_EQ(setrlimit(RLIMIT_AS, &saved), 0);
  // The headroom, less what the calls between the two readings mapped (a few pages).
  EXPECT_LE(available, headroom);
  EXPECT_GE(available, headroom - (std::size_t(16) << 20));
  // Half of 300 MB is below the floor of 512 MB.
  EXPECT_EQ(budget, std::size_t(512) << 20);
  // Without the limit: at least as much, and the budget is half of it where that is larger.
  const std::size_t unlimited = availableMemoryBytes();
  EXPECT_GT(unlimited, available);
  const std::size_t automatic = raymappers::automaticMemoryBudget();
  EXPECT_GE(automatic, std::size_t(512) << 20);
  if (unlimited / 2 > (std::size_t(600) << 20))
  {
    // MemAvailable moves between the two readings: within 10%.
    EXPECT_NEAR(static_cast<double>(automatic), unlimited / 2.0, unlimited * 0.05);
  }
}
