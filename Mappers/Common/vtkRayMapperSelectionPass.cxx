#include "vtkRayMapperSelectionPass.h"

#include "vtkDataObject.h"
#include "vtkHardwareSelector.h"
#include "vtkIdTypeArray.h"
#include "vtkRenderer.h"
#include "vtkUnsignedIntArray.h"

#include <array>
#include <cstdint>

namespace vtkRayMapperSelectionPass
{

vtkHardwareSelector* Of(vtkRenderer* ren)
{
  return ren ? ren->GetSelector() : nullptr;
}

bool SelectsPoints(vtkHardwareSelector* selector)
{
  return selector->GetFieldAssociation() == vtkDataObject::FIELD_ASSOCIATION_POINTS;
}

void Begin(vtkHardwareSelector* selector, vtkIdType maximumId)
{
  selector->BeginRenderProp();
  if (selector->GetCurrentPass() == vtkHardwareSelector::COMPOSITE_INDEX_PASS)
  {
    selector->RenderCompositeIndex(1);
  }
  if (SelectsPoints(selector))
  {
    selector->UpdateMaximumPointId(maximumId);
  }
  else
  {
    selector->UpdateMaximumCellId(maximumId);
  }
}

void End(vtkHardwareSelector* selector)
{
  selector->EndRenderProp();
}

namespace
{
// The 24 bits `value` as the 8-bit channels of a colour, red the low byte.
std::array<float, 3> Channels(std::uint64_t value)
{
  return { (value & 0xFFu) / 255.f, ((value >> 8) & 0xFFu) / 255.f,
    ((value >> 16) & 0xFFu) / 255.f };
}

// What the current pass writes for the drawn element `id`.
std::array<float, 3> PassColor(vtkHardwareSelector* selector,
  const Origins& origins,
  std::uint32_t id,
  const float propColor[3])
{
  const auto original = [&]
  {
    return static_cast<std::uint64_t>(origins.ids ? origins.ids->GetValue(id) : id);
  };
  switch (selector->GetCurrentPass())
  {
    case vtkHardwareSelector::POINT_ID_LOW24:
    case vtkHardwareSelector::CELL_ID_LOW24:
      return Channels(original());
    case vtkHardwareSelector::POINT_ID_HIGH24:
    case vtkHardwareSelector::CELL_ID_HIGH24:
      return Channels((original() >> 24) & 0xFFu);
    case vtkHardwareSelector::PROCESS_PASS:
      if (origins.processes && selector->GetUseProcessIdFromData())
      {
        return Channels(static_cast<std::uint64_t>(origins.processes->GetValue(id)) + 1);
      }
      return { propColor[0], propColor[1], propColor[2] };
    default:
      return { propColor[0], propColor[1], propColor[2] };
  }
}
}

void Encode(vtkHardwareSelector* selector,
  const raymappers::IdFrame& picks,
  const Origins& origins,
  raymappers::Frame& frame)
{
  frame.resize(picks.width, picks.height);
  float propColor[3];
  selector->GetPropColorValue(propColor);
  for (std::size_t p = 0; p < picks.ids.size(); ++p)
  {
    if (picks.ids[p] == 0)
    {
      continue;
    }
    const std::array<float, 3> c = PassColor(selector, origins, picks.ids[p] - 1u, propColor);
    frame.rgba[4 * p] = c[0];
    frame.rgba[4 * p + 1] = c[1];
    frame.rgba[4 * p + 2] = c[2];
    frame.rgba[4 * p + 3] = 1.f;
    frame.depth[p] = picks.depth[p];
  }
}

}
