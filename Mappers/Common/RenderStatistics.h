// What one render did: wall time per phase, event counters, and the effect plan (which
// optional effects the scene asked for and therefore ran). Counters of an effect that did
// not run stay at zero, which is how tests prove that an unused effect costs nothing.
#ifndef RayMappers_RenderStatistics_h
#define RayMappers_RenderStatistics_h

#include <chrono>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace raymappers
{

class RenderStatistics
{
public:
  void clear();

  /// Adds `ms` to the phase's time (creating it at first use, in order of first use).
  void addPhase(const std::string& name, double ms);
  /// Adds `n` to a counter (creating it at 0).
  void addCounter(const std::string& name, std::int64_t n);
  /// Declares a counter (so it reads 0 rather than absent when its effect is off).
  void declareCounter(const std::string& name) { addCounter(name, 0); }
  /// Records whether an optional effect ran in this render.
  void setEffect(const std::string& name, bool ran);

  double phase(const std::string& name) const;         // ms, 0 when absent
  std::int64_t counter(const std::string& name) const; // 0 when absent
  bool effect(const std::string& name) const;          // false when absent
  double totalMs() const;

  const std::vector<std::pair<std::string, double>>& phases() const { return Phases; }
  const std::vector<std::pair<std::string, std::int64_t>>& counters() const { return Counters; }
  const std::vector<std::pair<std::string, bool>>& effects() const { return Effects; }

  /// One line per entry: "phase NAME MS", "counter NAME N", "effect NAME on|off".
  std::string summary() const;

private:
  std::vector<std::pair<std::string, double>> Phases;
  std::vector<std::pair<std::string, std::int64_t>> Counters;
  std::vector<std::pair<std::string, bool>> Effects;
};

/// Measures the wall time of a scope into a phase of `stats`.
class ScopedPhase
{
public:
  ScopedPhase(RenderStatistics& stats, std::string name)
    : Stats(stats)
    , Name(std::move(name))
    , Start(std::chrono::steady_clock::now())
  {
  }
  ~ScopedPhase()
  {
    const auto end = std::chrono::steady_clock::now();
    Stats.addPhase(Name, std::chrono::duration<double, std::milli>(end - Start).count());
  }
  ScopedPhase(const ScopedPhase&) = delete;
  ScopedPhase& operator=(const ScopedPhase&) = delete;

private:
  RenderStatistics& Stats;
  std::string Name;
  std::chrono::steady_clock::time_point Start;
};

} // namespace raymappers

#endif
