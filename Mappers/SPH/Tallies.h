// Per-thread tallies of a kernel's counters: a struct of std::int64_t fields, one per counter,
// listed once with the counters' names; the statistics receive the sums over the threads.
#ifndef RayMappers_Tallies_h
#define RayMappers_Tallies_h

#include "Mappers/Common/RenderStatistics.h"

#include <cstddef>
#include <cstdint>

namespace raymappers
{

/// A counter of the statistics and the field of tally struct T that counts it.
template<typename T>
struct TallyField
{
  const char* name;
  std::int64_t T::*field;
};

/// Adds to each counter of `fields` its sum over the tallies: forEach(fn) calls fn(const T&)
/// for every tally.
template<typename T, std::size_t N, typename ForEach>
void addTallies(const TallyField<T> (&fields)[N], ForEach forEach, RenderStatistics& stats)
{
  for (const TallyField<T>& f : fields)
  {
    std::int64_t total = 0;
    forEach([&](const T& t) { total += t.*f.field; });
    stats.addCounter(f.name, total);
  }
}

} // namespace raymappers

#endif
