// Force-included into the second build of the engine, the schema and the api
// (tests/modules/CMakeLists.txt): appends the test-only law of power_law.hpp to the pair law list, the
// one line the recipe "add a pair force law" asks of a law in src/ (engine/pair_laws.hpp).
#pragma once
#include "power_law.hpp"
#define MESODPD_EXTRA_PAIR_LAWS , LawTable<test_models::PowerLaw>
