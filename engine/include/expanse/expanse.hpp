#pragma once
// Umbrella header.
#include "expanse/check.hpp"
#include "expanse/error.hpp"
#include "expanse/mesh.hpp"
#include "expanse/options.hpp"
#include "expanse/triangulate.hpp"
#include "expanse/types.hpp"
