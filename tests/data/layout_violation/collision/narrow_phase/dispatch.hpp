// The narrow phase may use shapes.
#pragma once
#include "collision/shapes/shape.hpp"
