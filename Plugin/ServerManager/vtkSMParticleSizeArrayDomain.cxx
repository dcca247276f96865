#include "vtkSMParticleSizeArrayDomain.h"

#include "vtkObjectFactory.h"
#include "vtkPVXMLElement.h"
#include "vtkRayMapperParticleSizes.h"
#include "vtkSMPropertyHelper.h"

#include <cstring>
#include <string>

vtkStandardNewMacro(vtkSMParticleSizeArrayDomain);

vtkSMParticleSizeArrayDomain::vtkSMParticleSizeArrayDomain() = default;

vtkSMParticleSizeArrayDomain::~vtkSMParticleSizeArrayDomain() = default;

int vtkSMParticleSizeArrayDomain::ReadXMLAttributes(vtkSMProperty* property,
  vtkPVXMLElement* element)
{
  if (!this->Superclass::ReadXMLAttributes(property, element))
  {
    return 0;
  }
  const char* role = element->GetAttribute("size_role");
  if (role && std::strcmp(role, "radius") != 0 && std::strcmp(role, "smoothing_length") != 0)
  {
    vtkErrorMacro("size_role must be \"radius\" or \"smoothing_length\", not \"" << role << "\".");
    return 0;
  }
  this->SmoothingLengthRole = role && std::strcmp(role, "smoothing_length") == 0;
  int acceptOther = 0;
  element->GetScalarAttribute("accept_other", &acceptOther);
  this->AcceptOther = acceptOther != 0;
  return 1;
}

const char* vtkSMParticleSizeArrayDomain::GetConventionalArray(double& scale)
{
  // The none_string entry ("None") is no size name, so it is never the one found.
  const auto role = this->SmoothingLengthRole ? vtkRayMapperParticleSizes::Role::SmoothingLength
                                              : vtkRayMapperParticleSizes::Role::Radius;
  const int found =
    vtkRayMapperParticleSizes::FindSizeName(this->GetStrings(), role, this->AcceptOther, scale);
  return found < 0 ? nullptr : this->GetString(static_cast<unsigned int>(found));
}

int vtkSMParticleSizeArrayDomain::SetDefaultValues(vtkSMProperty* property,
  bool useUncheckedValues)
{
  double scale = 1.0;
  const char* name = this->GetConventionalArray(scale);
  if (!name)
  {
    name = this->GetNoneString();
  }
  unsigned int index = 0;
  vtkSMPropertyHelper helper(property);
  helper.SetUseUnchecked(useUncheckedValues);
  if (!name || !this->IsInDomain(name, index) ||
    (helper.GetNumberOfElements() != 5 && helper.GetNumberOfElements() != 1))
  {
    return this->Superclass::SetDefaultValues(property, useUncheckedValues);
  }
  if (helper.GetNumberOfElements() == 5)
  {
    // SetInputArrayToProcess's (index, port, connection, association, name).
    helper.Set(3, std::to_string(this->GetFieldAssociation(index)).c_str());
  }
  helper.Set(helper.GetNumberOfElements() - 1, name);
  return 1;
}

void vtkSMParticleSizeArrayDomain::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "SizeRole: " << (this->SmoothingLengthRole ? "smoothing_length" : "radius")
     << "\n";
  os << indent << "AcceptOther: " << this->AcceptOther << "\n";
}
