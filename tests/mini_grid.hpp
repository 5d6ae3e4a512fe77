#pragma once
// The GelSight Mini's default marker grid, as the test scenes, fixtures and recordings use it.
namespace sbtest {

// 7 rows of 9 markers (33 px pitch): the marker count every default-sensor field has.
inline constexpr int kMiniMarkers = 7 * 9;

}  // namespace sbtest
