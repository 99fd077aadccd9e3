// tumble's public API in one include: math aliases, shapes, scene description, loading, the
// compiled model, World and its queries, batches of worlds, errors. docs/api.md walks through it.
#pragma once

#include "tumble/batch_world.hpp"
#include "tumble/body_state.hpp"
#include "tumble/distance.hpp"
#include "tumble/error.hpp"
#include "tumble/load_scene.hpp"
#include "tumble/math.hpp"
#include "tumble/model.hpp"
#include "tumble/randomization.hpp"
#include "tumble/scene.hpp"
#include "tumble/settings.hpp"
#include "tumble/shape.hpp"
#include "tumble/version.hpp"
#include "tumble/world.hpp"
