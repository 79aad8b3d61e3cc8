// The keys of the [analysis.*] tables, declared next to the analyses they configure.
#pragma once
#include "mesodpd/key_table.hpp"
#include "mesodpd/spec.hpp"

namespace mesodpd {

const keys::KeyTable<RdfSpec>& rdf_keys();
const keys::KeyTable<MsdSpec>& msd_keys();
const keys::KeyTable<FieldsSpec>& fields_keys();  // [analysis.fields] or each [[analysis.fields]]
const keys::KeyTable<SurfaceTensionSpec>& surface_tension_keys();
const keys::KeyTable<DropletSpec>& droplet_keys();
const keys::KeyTable<StressProfileSpec>& stress_profile_keys();

}  // namespace mesodpd
