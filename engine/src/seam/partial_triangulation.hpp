#pragma once
// PartialTriangulation is the backends' output: include backends/partial_triangulation.hpp.
// This name stays only until engine/src/backends/vulkan/vulkan_backend.hpp includes that.
#include "backends/partial_triangulation.hpp"
