// A public header that includes an internal one.
#pragma once
#include "collision/shapes/shape.hpp"
