#include "vtkRayMapperStatistics.h"

#include "Mappers/Common/RenderStatistics.h"

#include "vtkObjectFactory.h"

#include <cstdlib>
#include <string>

struct vtkRayMapperStatistics::Internals
{
  raymappers::RenderStatistics Stats;
  std::string Summary;
};

vtkStandardNewMacro(vtkRayMapperStatistics);

vtkRayMapperStatistics::vtkRayMapperStatistics()
  : Impl(new Internals)
{
  // Tests of the representations (pvpython, pvbatch) cannot reach the mappers' statistics
  // objects before the first render: the environment turns the validation on for all.
  const char* validate = std::getenv("RAYMAPPERS_VALIDATE_FRAMES");
  this->ValidateFrames = validate && *validate && std::string(validate) != "0";
}

vtkRayMapperStatistics::~vtkRayMapperStatistics() = default;

void vtkRayMapperStatistics::Set(const raymappers::RenderStatistics& stats)
{
  Impl->Stats = stats;
  this->Modified();
}

const raymappers::RenderStatistics& vtkRayMapperStatistics::Get() const
{
  return Impl->Stats;
}

double vtkRayMapperStatistics::GetPhaseTime(const char* name)
{
  return name ? Impl->Stats.phase(name) : 0.0;
}

double vtkRayMapperStatistics::GetTotalTime()
{
  return Impl->Stats.totalMs();
}

long long vtkRayMapperStatistics::GetCounter(const char* name)
{
  return name ? static_cast<long long>(Impl->Stats.counter(name)) : 0;
}

bool vtkRayMapperStatistics::GetEffect(const char* name)
{
  return name ? Impl->Stats.effect(name) : false;
}

int vtkRayMapperStatistics::GetNumberOfPhases()
{
  return static_cast<int>(Impl->Stats.phases().size());
}

const char* vtkRayMapperStatistics::GetPhaseName(int i)
{
  const auto& v = Impl->Stats.phases();
  return i >= 0 && i < static_cast<int>(v.size()) ? v[i].first.c_str() : nullptr;
}

int vtkRayMapperStatistics::GetNumberOfCounters()
{
  return static_cast<int>(Impl->Stats.counters().size());
}

const char* vtkRayMapperStatistics::GetCounterName(int i)
{
  const auto& v = Impl->Stats.counters();
  return i >= 0 && i < static_cast<int>(v.size()) ? v[i].first.c_str() : nullptr;
}

int vtkRayMapperStatistics::GetNumberOfEffects()
{
  return static_cast<int>(Impl->Stats.effects().size());
}

const char* vtkRayMapperStatistics::GetEffectName(int i)
{
  const auto& v = Impl->Stats.effects();
  return i >= 0 && i < static_cast<int>(v.size()) ? v[i].first.c_str() : nullptr;
}

const char* vtkRayMapperStatistics::GetSummary()
{
  Impl->Summary = Impl->Stats.summary();
  return Impl->Summary.c_str();
}

void vtkRayMapperStatistics::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "ValidateFrames: " << this->ValidateFrames << "\n";
  os << indent << "Summary:\n" << Impl->Stats.summary();
}
