#include "vtkRayMapperThreads.h"

#include "vtkLogger.h"

#include <tbb/global_control.h>

#include <algorithm>
#include <cstdlib>
#include <memory>
#include <thread>

namespace
{
int positiveEnvironment(const char* name)
{
  const char* value = std::getenv(name);
  const int n = value ? std::atoi(value) : 0;
  return n > 0 ? n : 0;
}

int chooseThreads()
{
  const int cores = std::max(1u, std::thread::hardware_concurrency());
  if (const int n = positiveEnvironment("RAYMAPPERS_THREADS"))
  {
    return n;
  }
  int local = positiveEnvironment("OMPI_COMM_WORLD_LOCAL_SIZE");
  if (!local)
  {
    local = positiveEnvironment("MPI_LOCALNRANKS");
  }
  return local > 1 ? std::max(1, cores / local) : 0;
}
}

int vtkRayMapperLimitThreads()
{
  // Lives as long as the process: the cap holds for every later parallel loop.
  static std::unique_ptr<tbb::global_control> cap;
  static const int threads = []
  {
    const int n = chooseThreads();
    if (n > 0)
    {
      cap = std::make_unique<tbb::global_control>(
        tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(n));
      vtkLogF(INFO, "RayMappers: %d thread(s) for the mappers of this process", n);
    }
    return n > 0 ? n : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  }();
  return threads;
}
