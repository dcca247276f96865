// How much memory this process can still take, for budgets that default to "automatic" (SPH
// Fluid's voxel tiles). The least of three limits, each where the system has it:
// - the physical memory the kernel could hand out without swapping (MemAvailable of
//   /proc/meminfo: free pages plus reclaimable caches);
// - the control group's limit less its usage (cgroup v2 memory.max - memory.current: a
//   container's or a batch job's share of the node);
// - the address-space limit less the address space in use (RLIMIT_AS - VmSize).
#ifndef RayMappers_AvailableMemory_h
#define RayMappers_AvailableMemory_h

#include <cstddef>

namespace raymappers
{

/// Bytes this process can still allocate (see above); 0 when no limit could be read.
std::size_t availableMemoryBytes();

} // namespace raymappers

#endif
