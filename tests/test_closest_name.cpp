#include <catch2/catch.hpp>

#include "core/base/closest_name.hpp"

// This file's names in a namespace of its own: the unity build compiles several test files as one unit.
namespace test_closest_name {

using namespace sb;

TEST_CASE("edit_distance: insertions, deletions, substitutions and neighbour swaps cost one each", "[closest_name]") {
  CHECK(edit_distance("", "") == 0);
  CHECK(edit_distance("", "fit") == 3);              // three insertions
  CHECK(edit_distance("evalute", "evaluate") == 1);  // one insertion ('a')
  CHECK(edit_distance("fost", "fots") == 1);         // one swap (s, t), not two substitutions
  CHECK(edit_distance("tacls", "tacsl") == 1);       // a swap at the end
  CHECK(edit_distance("kitten", "sitting") == 3);    // k->s, e->i, +g: the textbook case
  CHECK(edit_distance("render", "render") == 0);
}

TEST_CASE("closest_name: a slip of the keyboard is named, an unrelated word is not", "[closest_name]") {
  const std::vector<std::string> commands{"gui", "render", "simulate", "evaluate", "fit", "residual", "import"};
  CHECK(closest_name("evalute", commands) == "evaluate");   // 1 edit, 7 letters allow 2
  CHECK(closest_name("simualte", commands) == "simulate");  // 1 swap
  CHECK(closest_name("Render", commands) == "render");      // case is ignored
  // "fti": 1 swap from "fit", and 3 letters allow max(1, 3/3) = 1 edit.
  CHECK(closest_name("fti", commands) == "fit");
  // "gx": 2 edits from "gui" (x->u, +i) but 2 letters allow only 1: no suggestion.
  CHECK(closest_name("gx", commands).empty());
  CHECK(closest_name("calibrate", commands).empty());
  CHECK(closest_name("anything", {}).empty());
  CHECK(did_you_mean("evalute", commands) == " (did you mean 'evaluate'?)");
  CHECK(did_you_mean("calibrate", commands).empty());
}

TEST_CASE("closest_name: ties go to the first known name", "[closest_name]") {
  // "fots-x" is one substitution from both "fots-a" and "fots-b"; the first wins.
  CHECK(closest_name("fots-x", {"fots-a", "fots-b"}) == "fots-a");
}

}  // namespace test_closest_name
