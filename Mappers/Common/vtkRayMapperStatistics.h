/**
 * @class   vtkRayMapperStatistics
 * @brief   What a RayMappers mapper did in its last render: phase times, counters, effects.
 *
 * Readable from C++ and Python after a render, e.g.
 *   stats = mapper.GetStatistics()
 *   stats.GetCounter("rays"), stats.GetPhaseTime("trace"), stats.GetEffect("shading")
 * A counter or effect that the method has but did not use reads 0 / false; names that the
 * method does not know also read 0 / false (use GetNumberOfCounters/GetCounterName to list).
 *
 * Frame validation (ValidateFrames, default off): after each render that draws, the
 * mapper's own float frame (premultiplied RGBA + window depth, before OpenGL clamps and
 * rounds it) is scanned, and the statistics get the counters frame_nonfinite_values (NaN or
 * infinite rgba or depth values) and frame_out_of_range_values (alpha outside [0, 1], a
 * colour channel below 0 or above its alpha by more than 1e-5, depth outside [0, 1]) and the
 * effect frame_validation. Off, nothing is scanned and the three are absent (0 / off). It is
 * also on when the environment variable RAYMAPPERS_VALIDATE_FRAMES is set to a value other
 * than "0" (or empty) when the statistics object is created, which turns it on for the
 * mappers that ParaView's representations create in pvpython or pvbatch tests.
 */
#ifndef vtkRayMapperStatistics_h
#define vtkRayMapperStatistics_h

#include "RayMappersMappersModule.h"
#include "vtkObject.h"

#include <memory>

namespace raymappers
{
class RenderStatistics;
}

class RAYMAPPERSMAPPERS_EXPORT vtkRayMapperStatistics : public vtkObject
{
public:
  static vtkRayMapperStatistics* New();
  vtkTypeMacro(vtkRayMapperStatistics, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// Milliseconds spent in a phase of the last render (0 if the phase did not run).
  double GetPhaseTime(const char* name);
  /// Sum of all phase times, ms.
  double GetTotalTime();
  /// Value of a counter of the last render.
  long long GetCounter(const char* name);
  /// Whether an optional effect ran in the last render.
  bool GetEffect(const char* name);

  int GetNumberOfPhases();
  const char* GetPhaseName(int i);
  int GetNumberOfCounters();
  const char* GetCounterName(int i);
  int GetNumberOfEffects();
  const char* GetEffectName(int i);

  /// All of the above as text, one "phase|counter|effect NAME VALUE" per line.
  const char* GetSummary();

  ///@{
  /// Scan each drawn frame for NaN, infinite and out-of-range values (see above).
  vtkSetMacro(ValidateFrames, bool);
  vtkGetMacro(ValidateFrames, bool);
  vtkBooleanMacro(ValidateFrames, bool);
  ///@}

  /// Replaces the content (used by the mappers after each render).
  void Set(const raymappers::RenderStatistics& stats);
  const raymappers::RenderStatistics& Get() const;

protected:
  vtkRayMapperStatistics();
  ~vtkRayMapperStatistics() override;

  bool ValidateFrames = false;

private:
  vtkRayMapperStatistics(const vtkRayMapperStatistics&) = delete;
  void operator=(const vtkRayMapperStatistics&) = delete;
  struct Internals;
  std::unique_ptr<Internals> Impl;
};

#endif
