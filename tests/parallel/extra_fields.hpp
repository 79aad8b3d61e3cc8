// Two per-particle fields added the way docs/architecture.md's recipe says, for the field-list test:
// a density that ghosts carry and checkpoints keep, and a molecule id that migrates and is
// checkpointed but is not sent to ghosts. Force-included into a test build of the particle code.
#pragma once
#define MESODPD_EXTRA_PARTICLE_FIELDS(X)                                                  \
  X(double, rho, field::kMigrate | field::kGhost | field::kCheckpoint | field::kFrame)   \
  X(std::uint32_t, molecule, field::kMigrate | field::kCheckpoint)
