#pragma once
// Umbrella header for the crack2d layer (crack graph in a patch's parameter plane).
#include "crack2d/consistent_extraction.hpp"
#include "crack2d/crack_graph.hpp"
#include "crack2d/crack_index.hpp"
#include "crack2d/crack_paths.hpp"
#include "crack2d/geometry.hpp"
#include "crack2d/prescribed_cut.hpp"
