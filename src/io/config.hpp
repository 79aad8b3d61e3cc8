// The TOML reader's interface is public (include/mesodpd/config.hpp); engine code includes it here.
#pragma once
#include "mesodpd/config.hpp"
