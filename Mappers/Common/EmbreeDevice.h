// Creating the Embree devices of this project's builds (the CGT mapper's sphere BVH, the RBF
// particle BVH). Every one asks Embree for no tessellation cache: Embree 3 maps a cache of
// 128 MB for subdivision surfaces with each device (State::tessellation_cache_size), which no
// geometry here uses, and when that mapping fails (an address-space limit, a full control
// group) the cache's reallocation throws with every thread's use counter left blocked
// (SharedLazyTessellationCache::realloc, kernels/subdiv/tessellation_cache.cpp), so that the
// next reallocation, that of any later rtcReleaseDevice, spins forever waiting for them.
// Seen as TestRayMapperOutOfMemory hanging in rtcReleaseDevice (2 of 10 runs, with a build
// whose small temporaries came from the heap); TestEmbreeDevice.cxx provokes it every time.
#ifndef RayMappers_EmbreeDevice_h
#define RayMappers_EmbreeDevice_h

#include "Mappers/Common/EmbreeErrors.h"

#include <embree3/rtcore.h>

#include <stdexcept>
#include <string>

namespace raymappers
{

/// A new Embree device with `config` (nullptr or empty: Embree's defaults) and no
/// tessellation cache; throws as ThrowOnEmbreeError when Embree cannot create it.
inline RTCDevice NewEmbreeDevice(const char* config)
{
  std::string withoutCache = "tessellation_cache_size=0";
  if (config && *config)
  {
    withoutCache += std::string(",") + config;
  }
  RTCDevice device = rtcNewDevice(withoutCache.c_str());
  if (!device)
  {
    ThrowOnEmbreeError(nullptr, "rtcNewDevice");
    throw std::runtime_error("Embree: rtcNewDevice failed");
  }
  return device;
}

} // namespace raymappers

#endif
