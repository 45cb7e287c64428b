// The generated wire types: every sample survives conversion, CDR serialization through its
// Fast DDS type support and back; bounds are those of the plain structs; sizes that
// disagree with their fields are refused.
#include <gtest/gtest.h>

#include <fastdds/rtps/common/SerializedPayload.h>

#include "dds_test_samples.hpp"
#include "nav/dds/wire_convert.hpp"

namespace nav::dds {
namespace {

using namespace testing;

/// `sample` after to_wire, serialize, deserialize and from_wire.
template <typename Sample>
std::unique_ptr<Sample> round_trip(const Sample& sample) {
  using Traits = WireTraits<Sample>;
  typename Traits::PubSubType type;
  typename Traits::Wire wire_out;
  to_wire(sample, wire_out);
  eprosima::fastrtps::rtps::SerializedPayload_t payload(type.m_typeSize);
  EXPECT_TRUE(type.serialize(&wire_out, &payload));
  typename Traits::Wire wire_in;
  EXPECT_TRUE(type.deserialize(&payload, &wire_in));
  auto result = std::make_unique<Sample>();
  EXPECT_EQ(from_wire(wire_in, *result), SampleFault::none);
  return result;
}

TEST(DdsWireTypes, PoseRoundTripsExactly) {
  const ToolPose pose = make_pose(5, 123'456'789);
  const auto back = round_trip(pose);
  EXPECT_EQ(back->tool_id, 5u);
  EXPECT_EQ(back->source_time_ns, 123'456'789);
  EXPECT_EQ(back->position_m, pose.position_m);
  EXPECT_EQ(back->orientation_wxyz, pose.orientation_wxyz);
  EXPECT_EQ(back->position_covariance_m2, pose.position_covariance_m2);
  EXPECT_EQ(back->quality, pose.quality);
  EXPECT_STREQ(back->frame_to.data(), "tracker");
  EXPECT_STREQ(back->frame_from.data(), "needle");
}

TEST(DdsWireTypes, FullSizeFrameRoundTripsExactly) {
  const auto frame = make_frame(1024, 1024, 42);
  ASSERT_EQ(frame->pixel_count(), kMaxFramePixels);
  const auto back = round_trip(*frame);
  EXPECT_EQ(back->width_px, 1024u);
  EXPECT_EQ(back->height_px, 1024u);
  EXPECT_EQ(back->pixel_spacing_m, frame->pixel_spacing_m);
  EXPECT_EQ(back->depth_m, frame->depth_m);
  EXPECT_EQ(std::memcmp(back->pixels.data(), frame->pixels.data(), kMaxFramePixels), 0);
}

TEST(DdsWireTypes, NeedlePredictionSurfaceAndHealthRoundTrip) {
  const NeedleState needle = make_needle(kMaxNeedlePoints, 1);
  const auto needle_back = round_trip(needle);
  EXPECT_EQ(needle_back->point_count, kMaxNeedlePoints);
  EXPECT_EQ(needle_back->shape_points_m, needle.shape_points_m);
  EXPECT_EQ(needle_back->tip_force_n, needle.tip_force_n);

  const TargetPrediction prediction = make_prediction(2);
  const auto prediction_back = round_trip(prediction);
  EXPECT_EQ(prediction_back->horizon_ns, prediction.horizon_ns);
  EXPECT_EQ(prediction_back->model_rung, 2u);
  EXPECT_EQ(prediction_back->covariance_m2, prediction.covariance_m2);

  const auto surface = make_surface(kMaxSurfaceVertices, 3);
  const auto surface_back = round_trip(*surface);
  EXPECT_EQ(surface_back->vertex_count, kMaxSurfaceVertices);
  EXPECT_EQ(surface_back->vertex_positions_m, surface->vertex_positions_m);

  StationHealth health = make_health(4);
  health.boundary.non_unit_quaternion = 9;
  health.boundary.buffer_full = 11;
  health.boundary.malformed = 13;
  const auto health_back = round_trip(health);
  EXPECT_EQ(health_back->mode, StationMode::running);
  EXPECT_EQ(health_back->step_time_max_ns, 420'000);
  EXPECT_EQ(health_back->boundary.non_unit_quaternion, 9u);
  EXPECT_EQ(health_back->boundary.buffer_full, 11u);
  EXPECT_EQ(health_back->boundary.malformed, 13u);

  const GroundTruth truth = make_truth(5);
  const auto truth_back = round_trip(truth);
  EXPECT_EQ(truth_back->source_time_ns, 5);
  EXPECT_EQ(truth_back->tumour_m, truth.tumour_m);
  EXPECT_EQ(truth_back->needle_tip_m, truth.needle_tip_m);
}

TEST(DdsWireTypes, AllTypesAreBoundedSoTheyCanUseDataSharing) {
  EXPECT_TRUE(nav_msgs::ToolPosePubSubType().is_bounded());
  EXPECT_TRUE(nav_msgs::UltrasoundFramePubSubType().is_bounded());
  EXPECT_TRUE(nav_msgs::NeedleStatePubSubType().is_bounded());
  EXPECT_TRUE(nav_msgs::TargetPredictionPubSubType().is_bounded());
  EXPECT_TRUE(nav_msgs::DeformedSurfacePubSubType().is_bounded());
  EXPECT_TRUE(nav_msgs::StationHealthPubSubType().is_bounded());
  EXPECT_TRUE(nav_msgs::GroundTruthPubSubType().is_bounded());
  // A full frame fits the preallocated payload, with room for the header fields.
  EXPECT_GT(nav_msgs::UltrasoundFramePubSubType().m_typeSize, kMaxFramePixels);
  EXPECT_LT(nav_msgs::UltrasoundFramePubSubType().m_typeSize, kMaxFramePixels + 256);
}

TEST(DdsWireTypes, FrameWhosePixelCountDisagreesWithItsSizeIsRefused) {
  nav_msgs::UltrasoundFrame wire;
  wire.width_px(100);
  wire.height_px(100);
  wire.pixels().resize(100 * 99);
  auto frame = std::make_unique<UltrasoundFrame>();
  EXPECT_EQ(from_wire(wire, *frame), SampleFault::wrong_size);
  wire.width_px(2048);
  wire.height_px(1024);
  wire.pixels().resize(kMaxFramePixels);
  EXPECT_EQ(from_wire(wire, *frame), SampleFault::wrong_size);
}

TEST(DdsWireTypes, PointListsThatAreNotTriplesOrTooLongAreRefused) {
  nav_msgs::NeedleState needle_wire;
  needle_wire.shape_points_m().resize(10);
  NeedleState needle;
  EXPECT_EQ(from_wire(needle_wire, needle), SampleFault::wrong_size);
  needle_wire.shape_points_m().resize(3 * (kMaxNeedlePoints + 1));
  EXPECT_EQ(from_wire(needle_wire, needle), SampleFault::wrong_size);

  nav_msgs::DeformedSurface surface_wire;
  surface_wire.vertex_positions_m().resize(3 * kMaxSurfaceVertices + 3);
  auto surface = std::make_unique<DeformedSurface>();
  EXPECT_EQ(from_wire(surface_wire, *surface), SampleFault::wrong_size);
}

TEST(DdsWireTypes, UnknownStationModeIsRefused) {
  nav_msgs::StationHealth wire;
  wire.mode(17);
  StationHealth health;
  EXPECT_EQ(from_wire(wire, health), SampleFault::wrong_size);
}

TEST(DdsWireTypes, OversizedFrameCannotBeSerialized) {
  nav_msgs::UltrasoundFramePubSubType type;
  nav_msgs::UltrasoundFrame wire;
  wire.pixels().resize(kMaxFramePixels + 4096);
  eprosima::fastrtps::rtps::SerializedPayload_t payload(type.m_typeSize);
  EXPECT_FALSE(type.serialize(&wire, &payload));
}

}  // namespace
}  // namespace nav::dds
