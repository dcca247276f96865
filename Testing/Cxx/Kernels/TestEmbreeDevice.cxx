// NewEmbreeDevice (Mappers/Common/EmbreeDevice.h) under an address-space limit: a device
// made while little address space is left (where Embree's default 128 MB tessellation cache
// cannot be mapped) must leave Embree able to make and release devices once the limit is
// lifted. With Embree's default cache the second device's release (or creation) spins
// forever on the cache's thread counters that the failed mapping left blocked; the child
// process below then dies of its alarm and the test fails.
#include "Mappers/Common/EmbreeDevice.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <new>
#include <sys/resource.h>
#include <unistd.h>

namespace
{
// The address space this process has mapped (VmSize of /proc/self/status), in bytes.
rlim_t mappedBytes()
{
  FILE* f = std::fopen("/proc/self/status", "r");
  char line[256];
  unsigned long kb = 0;
  while (f && std::fgets(line, sizeof line, f))
  {
    if (std::sscanf(line, "VmSize: %lu kB", &kb) == 1)
    {
      break;
    }
  }
  if (f)
  {
    std::fclose(f);
  }
  return static_cast<rlim_t>(kb) * 1024;
}

// In the death test's child: a device under a limit of 64 MiB above what is mapped (it may
// or may not be made), then, the limit lifted, a device made and released; exit 0.
void deviceAfterALimit()
{
  alarm(20); // a spin in Embree ends the child here
  rlimit old{};
  getrlimit(RLIMIT_AS, &old);
  rlimit low = old;
  low.rlim_cur = mappedBytes() + (rlim_t(64) << 20);
  setrlimit(RLIMIT_AS, &low);
  try
  {
    rtcReleaseDevice(raymappers::NewEmbreeDevice(nullptr));
  }
  catch (const std::exception&)
  {
  }
  setrlimit(RLIMIT_AS, &old);
  rtcReleaseDevice(raymappers::NewEmbreeDevice("threads=2"));
  std::exit(0);
}
}

TEST(EmbreeDevice, ADeviceMadeUnderAnAddressSpaceLimitLeavesLaterDevicesReleasable)
{
  GTEST_FLAG_SET(death_test_style, "threadsafe"); // a fresh process: no TBB threads forked
  EXPECT_EXIT(deviceAfterALimit(), ::testing::ExitedWithCode(0), "");
}
