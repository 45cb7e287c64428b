#include "nav/dds/pose_inbox.hpp"

namespace nav::dds {

PoseInbox::PoseInbox(std::initializer_list<std::uint32_t> tool_ids, const PoseBounds& bounds) noexcept
    : bounds_(bounds) {
  for (const std::uint32_t id : tool_ids) {
    if (tool_count_ == kMaxTools) break;
    tools_[tool_count_++].id = id;
  }
}

int PoseInbox::slot_of(std::uint32_t tool_id) const noexcept {
  for (std::size_t slot = 0; slot < tool_count_; ++slot) {
    if (tools_[slot].id == tool_id) return static_cast<int>(slot);
  }
  return -1;
}

SampleFault PoseInbox::refuse(int slot, SampleFault fault) noexcept {
  if (slot >= 0) refused_[static_cast<std::size_t>(slot)].fetch_add(1, std::memory_order_relaxed);
  return fault;
}

void PoseInbox::on_refused(const ToolPose& pose, SampleFault fault) noexcept { refuse(slot_of(pose.tool_id), fault); }

SampleFault PoseInbox::offer(const ToolPose& pose) noexcept {
  const int slot = slot_of(pose.tool_id);
  if (slot < 0) return SampleFault::unknown_tool;
  Tool& tool = tools_[static_cast<std::size_t>(slot)];
  const SampleFault plausible = bounds_.check(pose, tool.accepted_any ? &tool.last_accepted : nullptr);
  if (plausible != SampleFault::none) return refuse(slot, plausible);
  const SampleFault order = tool.order.advance(pose.source_time_ns);
  if (order != SampleFault::none) return refuse(slot, order);
  tool.latest.write(pose);
  tool.last_accepted = pose;
  tool.accepted_any = true;
  accepted_.fetch_add(1, std::memory_order_relaxed);
  return SampleFault::none;
}

}  // namespace nav::dds
