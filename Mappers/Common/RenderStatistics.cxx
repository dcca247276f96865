#include "Mappers/Common/RenderStatistics.h"

#include <sstream>

namespace raymappers
{

namespace
{
template<typename T>
T* find(std::vector<std::pair<std::string, T>>& v, const std::string& name)
{
  for (auto& e : v)
  {
    if (e.first == name)
    {
      return &e.second;
    }
  }
  return nullptr;
}
template<typename T>
const T* find(const std::vector<std::pair<std::string, T>>& v, const std::string& name)
{
  for (const auto& e : v)
  {
    if (e.first == name)
    {
      return &e.second;
    }
  }
  return nullptr;
}
}

void RenderStatistics::clear()
{
  Phases.clear();
  Counters.clear();
  Effects.clear();
}

void RenderStatistics::addPhase(const std::string& name, double ms)
{
  if (double* p = find(Phases, name))
  {
    *p += ms;
  }
  else
  {
    Phases.emplace_back(name, ms);
  }
}

void RenderStatistics::addCounter(const std::string& name, std::int64_t n)
{
  if (std::int64_t* c = find(Counters, name))
  {
    *c += n;
  }
  else
  {
    Counters.emplace_back(name, n);
  }
}

void RenderStatistics::setEffect(const std::string& name, bool ran)
{
  if (bool* e = find(Effects, name))
  {
    *e = ran;
  }
  else
  {
    Effects.emplace_back(name, ran);
  }
}

double RenderStatistics::phase(const std::string& name) const
{
  const double* p = find(Phases, name);
  return p ? *p : 0.0;
}

std::int64_t RenderStatistics::counter(const std::string& name) const
{
  const std::int64_t* c = find(Counters, name);
  return c ? *c : 0;
}

bool RenderStatistics::effect(const std::string& name) const
{
  const bool* e = find(Effects, name);
  return e ? *e : false;
}

double RenderStatistics::totalMs() const
{
  double t = 0;
  for (const auto& p : Phases)
  {
    t += p.second;
  }
  return t;
}

std::string RenderStatistics::summary() const
{
  std::ostringstream s;
  for (const auto& p : Phases)
  {
    s << "phase " << p.first << " " << p.second << "\n";
  }
  for (const auto& c : Counters)
  {
    s << "counter " << c.first << " " << c.second << "\n";
  }
  for (const auto& e : Effects)
  {
    s << "effect " << e.first << " " << (e.second ? "on" : "off") << "\n";
  }
  return s.str();
}

} // namespace raymappers
