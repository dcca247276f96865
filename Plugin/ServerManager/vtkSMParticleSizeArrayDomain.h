/**
 * @class   vtkSMParticleSizeArrayDomain
 * @brief   The arrays of a particle size property; the default is the input's size array.
 *
 * An array list domain (vtkSMArrayListDomain: the same list, the same XML attributes) whose
 * default is the array that conventionally holds the particles' size
 * (vtkRayMapperParticleSizes::FindSizeName: "radius", "radii", "r", "diameter" ...; "h",
 * "hsml", "smoothing_length" ...), when the list has one. Otherwise the default is the
 * none_string entry when the XML gives one ("None": the constant size), else what
 * vtkSMArrayListDomain picks.
 *
 * XML (tag ParticleSizeArrayDomain), besides vtkSMArrayListDomain's attributes:
 * \li \c size_role : "radius" (a sphere's radius, the default) or "smoothing_length"
 *                    (an SPH smoothing length h): which names come first.
 * \li \c accept_other : "1" to fall back to the other role's names (an RBF or fluid radius
 *                    from h, a smoothing length from a radius); "0" (the default) not to.
 *
 * The properties that go with the array (use the array, its scale) take their defaults from
 * this choice through vtkSMParticleSizeDefaultDomain.
 */
#ifndef vtkSMParticleSizeArrayDomain_h
#define vtkSMParticleSizeArrayDomain_h

#include "RayMappersServerManagerModule.h" // for export macro
#include "vtkSMArrayListDomain.h"

class RAYMAPPERSSERVERMANAGER_EXPORT vtkSMParticleSizeArrayDomain : public vtkSMArrayListDomain
{
public:
  static vtkSMParticleSizeArrayDomain* New();
  vtkTypeMacro(vtkSMParticleSizeArrayDomain, vtkSMArrayListDomain);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /**
   * The array of the list that conventionally holds the size, and in `scale` the factor
   * that turns its values into the size (0.5 for a diameter, else 1); nullptr (scale 1)
   * when the list has none.
   */
  const char* GetConventionalArray(double& scale);

  /**
   * Sets the property to the conventional array (point association), else to the
   * none_string entry, else does what vtkSMArrayListDomain does.
   */
  int SetDefaultValues(vtkSMProperty* property, bool useUncheckedValues) override;

protected:
  vtkSMParticleSizeArrayDomain();
  ~vtkSMParticleSizeArrayDomain() override;

  int ReadXMLAttributes(vtkSMProperty* property, vtkPVXMLElement* element) override;

private:
  vtkSMParticleSizeArrayDomain(const vtkSMParticleSizeArrayDomain&) = delete;
  void operator=(const vtkSMParticleSizeArrayDomain&) = delete;

  bool SmoothingLengthRole = false;
  bool AcceptOther = false;
};

#endif
