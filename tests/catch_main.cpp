// Catch2 v2 main, compiled once in its own translation unit (it is expensive).
#define CATCH_CONFIG_MAIN
#include <catch2/catch.hpp>
