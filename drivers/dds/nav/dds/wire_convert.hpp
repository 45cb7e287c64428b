#pragma once
// Internal (includes the generated types): conversion between the plain samples and their
// DDS wire types, and the traits that tie each plain sample to its wire type and topic.
// from_wire() refuses wire samples whose sizes disagree with their fields or bounds.
#include "nav/dds/sample_fault.hpp"
#include "nav/dds/samples.hpp"
#include "nav/dds/topics.hpp"
#include "nav_msgs.h"
#include "nav_msgsPubSubTypes.h"

namespace nav::dds {

void to_wire(const ToolPose& sample, nav_msgs::ToolPose& wire);
void to_wire(const UltrasoundFrame& sample, nav_msgs::UltrasoundFrame& wire);
void to_wire(const NeedleState& sample, nav_msgs::NeedleState& wire);
void to_wire(const TargetPrediction& sample, nav_msgs::TargetPrediction& wire);
void to_wire(const DeformedSurface& sample, nav_msgs::DeformedSurface& wire);
void to_wire(const StationHealth& sample, nav_msgs::StationHealth& wire);
void to_wire(const GroundTruth& sample, nav_msgs::GroundTruth& wire);
void to_wire(const NeedleForce& sample, nav_msgs::NeedleForce& wire);

/// Fill `sample` from `wire`: none, or wrong_size (then `sample` is partly written).
SampleFault from_wire(const nav_msgs::ToolPose& wire, ToolPose& sample) noexcept;
SampleFault from_wire(const nav_msgs::UltrasoundFrame& wire, UltrasoundFrame& sample) noexcept;
SampleFault from_wire(const nav_msgs::NeedleState& wire, NeedleState& sample) noexcept;
SampleFault from_wire(const nav_msgs::TargetPrediction& wire, TargetPrediction& sample) noexcept;
SampleFault from_wire(const nav_msgs::DeformedSurface& wire, DeformedSurface& sample) noexcept;
SampleFault from_wire(const nav_msgs::StationHealth& wire, StationHealth& sample) noexcept;
SampleFault from_wire(const nav_msgs::GroundTruth& wire, GroundTruth& sample) noexcept;
SampleFault from_wire(const nav_msgs::NeedleForce& wire, NeedleForce& sample) noexcept;

/// A plain sample's wire type, its Fast DDS type support and its topic.
template <typename Sample>
struct WireTraits;

template <>
struct WireTraits<ToolPose> {
  using Wire = nav_msgs::ToolPose;
  using PubSubType = nav_msgs::ToolPosePubSubType;
  static constexpr Topic topic = Topic::tool_pose;
};
template <>
struct WireTraits<UltrasoundFrame> {
  using Wire = nav_msgs::UltrasoundFrame;
  using PubSubType = nav_msgs::UltrasoundFramePubSubType;
  static constexpr Topic topic = Topic::ultrasound_frame;
};
template <>
struct WireTraits<NeedleState> {
  using Wire = nav_msgs::NeedleState;
  using PubSubType = nav_msgs::NeedleStatePubSubType;
  static constexpr Topic topic = Topic::needle_state;
};
template <>
struct WireTraits<TargetPrediction> {
  using Wire = nav_msgs::TargetPrediction;
  using PubSubType = nav_msgs::TargetPredictionPubSubType;
  static constexpr Topic topic = Topic::target_prediction;
};
template <>
struct WireTraits<DeformedSurface> {
  using Wire = nav_msgs::DeformedSurface;
  using PubSubType = nav_msgs::DeformedSurfacePubSubType;
  static constexpr Topic topic = Topic::deformed_surface;
};
template <>
struct WireTraits<StationHealth> {
  using Wire = nav_msgs::StationHealth;
  using PubSubType = nav_msgs::StationHealthPubSubType;
  static constexpr Topic topic = Topic::station_health;
};
template <>
struct WireTraits<GroundTruth> {
  using Wire = nav_msgs::GroundTruth;
  using PubSubType = nav_msgs::GroundTruthPubSubType;
  static constexpr Topic topic = Topic::ground_truth;
};
template <>
struct WireTraits<NeedleForce> {
  using Wire = nav_msgs::NeedleForce;
  using PubSubType = nav_msgs::NeedleForcePubSubType;
  static constexpr Topic topic = Topic::needle_force;
};

}  // namespace nav::dds
