#pragma once
#include "core/base/error.hpp"
