#pragma once
// The latest pose of each tool the station knows, handed from the DDS listener to the
// real-time thread through one triple buffer per tool: the listener never waits for the
// core and the core always reads the newest complete pose.
#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <initializer_list>

#include "nav/core/triple_buffer.hpp"
#include "nav/dds/sample_checks.hpp"
#include "nav/dds/sample_sink.hpp"

namespace nav::dds {

inline constexpr std::size_t kMaxTools = 8;

/// Per-tool latest-pose hand-off. offer() runs on one I/O thread (the pose listener);
/// update()/latest() run on the real-time thread. Poses of tools not configured are refused,
/// and so are poses outside `bounds` (PoseBounds) and poses older than the tool's previous one;
/// every refused pose of a configured tool, here or at the boundary before, counts for its tool.
class PoseInbox final : public SampleSink<ToolPose> {
 public:
  /// The tools to accept, by id (at most kMaxTools; extra ids are ignored).
  explicit PoseInbox(std::initializer_list<std::uint32_t> tool_ids, const PoseBounds& bounds = {}) noexcept;

  SampleFault offer(const ToolPose& pose) noexcept override;
  void on_refused(const ToolPose& pose, SampleFault fault) noexcept override;

  /// The slot of `tool_id`, or -1 when the tool is not configured.
  int slot_of(std::uint32_t tool_id) const noexcept;
  std::size_t tool_count() const noexcept { return tool_count_; }

  /// Real-time side: takes the newest pose of the tool in `slot`; true when it changed.
  bool update(std::size_t slot) noexcept { return tools_[slot].latest.update(); }
  /// Real-time side: the pose taken by the last update() of `slot` (default before any).
  const ToolPose& latest(std::size_t slot) const noexcept { return tools_[slot].latest.read(); }

  /// Poses accepted by offer() so far, every tool together (any thread): with the poses
  /// taken by update(), it tells how many a newer pose replaced before they were taken.
  std::uint64_t accepted() const noexcept { return accepted_.load(std::memory_order_relaxed); }
  /// Poses of the tool in `slot` refused so far (any thread).
  std::uint64_t refused(std::size_t slot) const noexcept { return refused_[slot].load(std::memory_order_relaxed); }

 private:
  /// One tool's id, its hand-off and, writer side, the time order of its stream and its last
  /// accepted pose.
  struct Tool {
    std::uint32_t id = 0;
    TripleBuffer<ToolPose> latest;
    StreamOrder order;
    ToolPose last_accepted;
    bool accepted_any = false;
  };
  PoseBounds bounds_;
  std::array<Tool, kMaxTools> tools_{};
  std::size_t tool_count_ = 0;
  std::atomic<std::uint64_t> accepted_{0};
  std::array<std::atomic<std::uint64_t>, kMaxTools> refused_{};
  /// Counts a refusal for `slot` and returns its fault.
  SampleFault refuse(int slot, SampleFault fault) noexcept;
};

}  // namespace nav::dds
