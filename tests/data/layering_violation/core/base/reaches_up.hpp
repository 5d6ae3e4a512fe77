#pragma once
// A low folder reaching up: the layering test must reject this fixture.
#include "core/models/model.hpp"
