#include "Mappers/Common/AvailableMemory.h"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>

namespace raymappers
{
namespace
{
constexpr std::size_t Unknown = std::numeric_limits<std::size_t>::max();

/// The value of a "Key:   N kB" line of a /proc file, in bytes (Unknown when absent).
std::size_t procKilobytes(const char* file, const std::string& key)
{
  std::ifstream in(file);
  std::string line;
  while (std::getline(in, line))
  {
    if (line.rfind(key, 0) == 0)
    {
      std::istringstream fields(line.substr(key.size()));
      std::uint64_t kb = 0;
      return fields >> kb ? static_cast<std::size_t>(kb) * 1024 : Unknown;
    }
  }
  return Unknown;
}

/// One number of a cgroup file ("max" or absent: Unknown).
std::size_t cgroupBytes(const std::string& file)
{
  std::ifstream in(file);
  std::uint64_t value = 0;
  return in >> value ? static_cast<std::size_t>(value) : Unknown;
}

/// The cgroup v2 limit less its usage for this process's group (/proc/self/cgroup "0::/path";
/// in a container the group is the namespace's root).
std::size_t cgroupHeadroom()
{
  std::ifstream in("/proc/self/cgroup");
  std::string line, path;
  while (std::getline(in, line))
  {
    if (line.rfind("0::", 0) == 0)
    {
      path = line.substr(3);
    }
  }
  const std::string dir = "/sys/fs/cgroup" + (path == "/" ? std::string() : path);
  const std::size_t limit = cgroupBytes(dir + "/memory.max");
  const std::size_t used = cgroupBytes(dir + "/memory.current");
  if (limit == Unknown || used == Unknown)
  {
    return Unknown;
  }
  return limit > used ? limit - used : 0;
}

/// RLIMIT_AS less the address space in use (VmSize).
std::size_t addressSpaceHeadroom()
{
  rlimit limit{};
  if (getrlimit(RLIMIT_AS, &limit) != 0 || limit.rlim_cur == RLIM_INFINITY)
  {
    return Unknown;
  }
  const std::size_t used = procKilobytes("/proc/self/status", "VmSize:");
  const std::size_t cap = static_cast<std::size_t>(limit.rlim_cur);
  return used == Unknown ? cap : (cap > used ? cap - used : 0);
}

/// MemAvailable, or the free pages where the kernel does not report it.
std::size_t physicalAvailable()
{
  const std::size_t available = procKilobytes("/proc/meminfo", "MemAvailable:");
  if (available != Unknown)
  {
    return available;
  }
  const long pages = sysconf(_SC_AVPHYS_PAGES), size = sysconf(_SC_PAGESIZE);
  return pages > 0 && size > 0 ? static_cast<std::size_t>(pages) * static_cast<std::size_t>(size)
                               : Unknown;
}
} // namespace

std::size_t availableMemoryBytes()
{
  const std::size_t least =
    std::min({ physicalAvailable(), cgroupHeadroom(), addressSpaceHeadroom() });
  return least == Unknown ? 0 : least;
}

} // namespace raymappers
