// A shape that reaches up into the narrow phase: against the direction.
#include "collision/narrow_phase/dispatch.hpp"
