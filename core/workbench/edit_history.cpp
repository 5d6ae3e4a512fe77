#include "core/workbench/edit_history.hpp"

#include <algorithm>
#include <stdexcept>
#include <utility>

namespace sb {

namespace {
// Whether two states change the same thing: the path, or the same model's table.
bool same_target(const EditState& a, const EditState& b) {
  if (a.index() != b.index()) return false;
  const auto* pa = std::get_if<ParamsEditState>(&a);
  const auto* pb = std::get_if<ParamsEditState>(&b);
  return pa == nullptr || pa->model == pb->model;
}

std::size_t poses_in(const EditState& s) {
  const auto* p = std::get_if<PathEditState>(&s);
  return p != nullptr && p->path ? p->path->size() : 0;
}

bool is_table_of(const EditState& s, std::size_t model) {
  const auto* p = std::get_if<ParamsEditState>(&s);
  return p != nullptr && p->model == model;
}
}  // namespace

EditHistory::EditHistory(std::size_t capacity, std::size_t max_stored_poses)
    : capacity_(capacity), max_stored_poses_(max_stored_poses) {
  if (capacity_ < 1) throw std::invalid_argument("EditHistory: capacity must be >= 1");
}

bool EditHistory::extends_newest(const EditEntry& entry) const {
  return entry.gesture != 0 && !undo_.empty() && undo_.back().gesture == entry.gesture &&
         same_target(undo_.back().after, entry.after);
}

void EditHistory::record(EditEntry entry) {
  const bool extends = redo_.empty() && extends_newest(entry);
  redo_.clear();
  if (extends) {
    undo_.back().after = std::move(entry.after);
  } else {
    undo_.push_back(std::move(entry));
  }
  trim();
}

std::optional<EditEntry> EditHistory::undo() {
  if (undo_.empty()) return std::nullopt;
  redo_.push_back(std::move(undo_.back()));
  undo_.pop_back();
  return redo_.back();
}

std::optional<EditEntry> EditHistory::redo() {
  if (redo_.empty()) return std::nullopt;
  undo_.push_back(std::move(redo_.back()));
  redo_.pop_back();
  return undo_.back();
}

void EditHistory::forget_model(std::size_t model) {
  const auto of_model = [model](const EditEntry& e) { return is_table_of(e.after, model); };
  undo_.erase(std::remove_if(undo_.begin(), undo_.end(), of_model), undo_.end());
  redo_.erase(std::remove_if(redo_.begin(), redo_.end(), of_model), redo_.end());
}

void EditHistory::clear() {
  undo_.clear();
  redo_.clear();
}

// Counts a path shared by two entries twice: the bound is on the worst case, where none is shared.
std::size_t EditHistory::stored_poses() const {
  std::size_t n = 0;
  for (const EditEntry& e : undo_) n += poses_in(e.before) + poses_in(e.after);
  return n;
}

// The newest entry always stays, however long its paths: the edit just made can be undone.
void EditHistory::trim() {
  while (undo_.size() > capacity_) undo_.pop_front();
  while (undo_.size() > 1 && stored_poses() > max_stored_poses_) undo_.pop_front();
}

}  // namespace sb
