// The keys of [[bond_type]], [[angle_type]], [[dihedral_type]], [[molecule]] and [bonds], declared next to the bonded forces
// and the molecule builder they configure.
#pragma once
#include "mesodpd/key_table.hpp"
#include "mesodpd/spec.hpp"

namespace mesodpd {

const keys::KeyTable<SimulationSpec>& bonds_keys();
const keys::KeyTable<BondTypeSpec>& bond_type_keys();
const keys::KeyTable<AngleTypeSpec>& angle_type_keys();
const keys::KeyTable<DihedralTypeSpec>& dihedral_type_keys();
const keys::KeyTable<MoleculeSpec>& molecule_keys();

}  // namespace mesodpd
