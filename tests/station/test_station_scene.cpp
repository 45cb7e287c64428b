// The scene loader: the example scenes parse into the values they state; every kind of
// error (YAML syntax, unknown key, wrong type, out of range, missing key, bad choice,
// repeated key, inconsistent values, unreadable file) names the file, the line of the key
// at fault (counted here in the text itself) and its key path; the reduced liver's
// escalation ladder (`liver.model.escalation`) reads into its rungs and options.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "nav/station/scene.hpp"
#include "scene_text.hpp"

namespace nav::station {
namespace {

using testing::demo_text;
using testing::edited;
using testing::example_scene_path;
using testing::line_of;

/// The Error of `text` parsed as the demo scene's file; fails the test if it parses.
Error error_of(const std::string& text) {
  const auto scene = parse_scene(text, example_scene_path("demo.yaml"));
  EXPECT_FALSE(scene.ok());
  return scene.ok() ? Error{} : scene.error();
}

/// Checks the error of `base` with `from` replaced by `to`: its file, the line where `to`
/// stands, its key path and a word of its message.
void expect_error_in(const std::string& base, const std::string& from, const std::string& to, const std::string& field,
                     const std::string& word) {
  const std::string text = edited(base, from, to);
  const Error error = error_of(text);
  EXPECT_EQ(error.file, example_scene_path("demo.yaml"));
  EXPECT_EQ(error.line, line_of(text, to)) << error.describe();
  EXPECT_EQ(error.field, field) << error.describe();
  EXPECT_NE(error.message.find(word), std::string::npos) << error.describe();
  EXPECT_NE(error.message.find("(column "), std::string::npos) << error.describe();
}

/// As expect_error_in, on the demo scene.
void expect_error(const std::string& from, const std::string& to, const std::string& field, const std::string& word) {
  expect_error_in(demo_text(), from, to, field, word);
}

TEST(StationScene, DemoSceneParsesIntoItsStatedValues) {
  const auto parsed = load_scene(example_scene_path("demo.yaml"));
  ASSERT_TRUE(parsed.ok()) << parsed.error().describe();
  const Scene& s = parsed.value();
  EXPECT_EQ(s.station.name, "demo");
  EXPECT_EQ(s.station.loop_rate_hz, 1000.0);
  EXPECT_EQ(s.station.tissue_rate_hz, 100.0);
  EXPECT_EQ(s.station.realtime_core, 1);
  EXPECT_EQ(s.station.io_core, 0);
  const std::filesystem::path folder = std::filesystem::path(example_scene_path("demo.yaml")).parent_path();
  EXPECT_EQ(s.frames.urdf_path, (folder / "../../../calibration/urdf/station.urdf").lexically_normal().string());
  EXPECT_EQ(s.liver.mesh.source, LiverMeshSource::generated);
  EXPECT_EQ(s.liver.rung, LiverRung::full);
  EXPECT_EQ(s.liver.full.integrator, Integrator::implicit_euler);
  EXPECT_DOUBLE_EQ(s.liver.full.step_s, 0.01);  // 1 / tissue_rate_hz
  EXPECT_FALSE(s.liver.tumour_m.has_value());
  ASSERT_TRUE(s.needle.has_value());
  EXPECT_DOUBLE_EQ(s.needle->parameters.step_s, 0.001);  // 1 / loop_rate_hz
  EXPECT_EQ(s.needle->parameters.outer_diameter_m, 0.00127);
  ASSERT_EQ(s.needle->interaction.layers.size(), 2u);
  EXPECT_EQ(s.needle->interaction.layers[1].puncture_force_n, 2.0);
  ASSERT_EQ(s.needle->layer_surfaces.size(), 2u);  // the capsule, then the tumour's elements
  ASSERT_TRUE(s.needle->layer_surfaces[0] && s.needle->layer_surfaces[1]);
  EXPECT_EQ(s.needle->layer_surfaces[0]->region, -1);
  EXPECT_EQ(s.needle->layer_surfaces[1]->region, static_cast<std::int32_t>(TissueRegion::tumour));
  EXPECT_EQ(s.needle->missing_compliance_radius_m, 0.015);
  EXPECT_EQ(s.needle->point_force_own_share, 0.5);
  EXPECT_FALSE(s.ligaments.has_value());
  EXPECT_EQ(s.devices.tracker.kind, TrackerKind::simulated);
  EXPECT_EQ(s.devices.tracker.position_noise_m, 0.00025);
  EXPECT_EQ(s.devices.ultrasound.kind, UltrasoundKind::simulated);
  EXPECT_EQ(s.devices.ultrasound.target_noise_m, 0.001);
  EXPECT_EQ(s.devices.tracker.volume_radius_m, 3.0);
  EXPECT_EQ(s.devices.tracker.max_speed_m_per_s, 2.0);
  EXPECT_EQ(s.devices.clock.offset_ms, 0.0);
  EXPECT_EQ(s.devices.clock.max_ahead_ms, 50.0);
  EXPECT_EQ(s.devices.clock.max_behind_ms, 1000.0);
  EXPECT_EQ(s.topics.poses, "nav/tool_pose");
}

TEST(StationScene, ReducedSceneResolvesItsPathsAgainstItsOwnFolder) {
  const auto parsed = load_scene(example_scene_path("liver_reduced.yaml"));
  ASSERT_TRUE(parsed.ok()) << parsed.error().describe();
  const Scene& s = parsed.value();
  const std::filesystem::path folder = std::filesystem::path(example_scene_path("liver_reduced.yaml")).parent_path();
  EXPECT_EQ(s.liver.mesh.source, LiverMeshSource::file);
  EXPECT_EQ(s.liver.mesh.path, (folder / "../../../../shared/data/liver/liverFine.vtu").lexically_normal().string());
  EXPECT_EQ(s.liver.mesh.unit, LengthUnit::centimetre);
  EXPECT_EQ(s.liver.rung, LiverRung::reduced);
  EXPECT_EQ(s.liver.reduced_artifact_path, (folder / "../../../build/liver_fine.navrb").lexically_normal().string());
  EXPECT_DOUBLE_EQ(s.liver.reduced.step_s, 1.0 / 500.0);
  ASSERT_TRUE(s.liver.escalation.has_value());
  ASSERT_EQ(s.liver.escalation->rungs.size(), 1u);
  EXPECT_EQ(s.liver.escalation->rungs[0].artifact_path,
            (folder / "../../../build/liver_fine_r32.navrb").lexically_normal().string());
  EXPECT_EQ(s.liver.escalation->options.de_escalate_after_steps, 200);
  ASSERT_TRUE(s.liver.tumour_m.has_value());
  EXPECT_EQ((*s.liver.tumour_m)[1], 0.032);
  EXPECT_FALSE(s.needle.has_value());
  EXPECT_EQ(s.devices.tracker.kind, TrackerKind::ndi);
  EXPECT_EQ(s.devices.tracker.port, 8765);
  EXPECT_EQ(s.devices.ultrasound.kind, UltrasoundKind::plus);
  EXPECT_EQ(s.topics.surfaces, "nav/deformed_surface");  // the default when `topics:` is absent
}

TEST(StationScene, TheTrackedToolsTakeTheirIdsFromTheScene) {
  const std::string from = "    kind: simulated\n    rate_hz: 60";
  const auto scene =
      parse_scene(edited(demo_text(), from, from + "\n    tools: {needle: 11, probe: 12, respiratory: 13}"),
                  example_scene_path("demo.yaml"));
  ASSERT_TRUE(scene.ok()) << scene.error().describe();
  const ToolIds& tools = scene.value().devices.tracker.tools;
  EXPECT_EQ(tools.needle, 11u);
  EXPECT_EQ(tools.probe, 12u);
  EXPECT_EQ(tools.respiratory, 13u);
  // Without the key: the demo's ids.
  EXPECT_EQ(parse_scene(demo_text(), example_scene_path("demo.yaml")).value().devices.tracker.tools.probe, 2u);
  // Two roles on one id: refused, naming the tools' map.
  const std::string text = edited(demo_text(), from, from + "\n    tools: {needle: 4, probe: 4}");
  const Error error = error_of(text);
  EXPECT_EQ(error.field, "devices.tracker.tools") << error.describe();
  EXPECT_NE(error.message.find("need an id each"), std::string::npos) << error.describe();
}

TEST(StationScene, AnNdiTrackersPortHandlesAreItsToolsAndEachOneIsOwn) {
  const std::string port = "    port: 8765";
  const auto parsed =
      parse_scene(edited(testing::file_text(example_scene_path("liver_reduced.yaml")), port,
                         port + "\n    rate_hz: 40\n    port_handles: {needle: 10, probe: 11, respiratory: 12}"),
                  example_scene_path("liver_reduced.yaml"));
  ASSERT_TRUE(parsed.ok()) << parsed.error().describe();
  const TrackerSettings& t = parsed.value().devices.tracker;
  EXPECT_EQ(t.port_handles.needle, 10u);
  EXPECT_EQ(t.port_handles.respiratory, 12u);
  EXPECT_EQ(t.rate_hz, 40.0);
  EXPECT_EQ(load_scene(example_scene_path("liver_reduced.yaml")).value().devices.tracker.port_handles.probe,
            2u);  // the default
  const auto twice = parse_scene(edited(testing::file_text(example_scene_path("liver_reduced.yaml")), port,
                                        port + "\n    port_handles: {needle: 3}"),
                                 example_scene_path("liver_reduced.yaml"));
  ASSERT_FALSE(twice.ok());
  EXPECT_EQ(twice.error().field, "devices.tracker.port_handles") << twice.error().describe();
  const auto out_of_range = parse_scene(edited(testing::file_text(example_scene_path("liver_reduced.yaml")), port,
                                               port + "\n    port_handles: {probe: 256}"),
                                        example_scene_path("liver_reduced.yaml"));
  ASSERT_FALSE(out_of_range.ok());
  EXPECT_EQ(out_of_range.error().field, "devices.tracker.port_handles.probe") << out_of_range.error().describe();
}

TEST(StationScene, ACaptureSourceReadsItsClipAndSpacing) {
  const std::string simulated =
      "  ultrasound:\n    kind: simulated\n    rate_hz: 20\n    target_noise_m: 0.001\n    seed: 2";
  const std::string capture =
      "  ultrasound:\n    kind: capture\n    source: frames/%04d.png\n    clip_px: [4, 8, 640, 480]\n"
      "    pixel_spacing_mm: [0.1, 0.12]";
  const auto parsed = parse_scene(edited(demo_text(), simulated, capture), example_scene_path("demo.yaml"));
  ASSERT_TRUE(parsed.ok()) << parsed.error().describe();
  const UltrasoundSettings& u = parsed.value().devices.ultrasound;
  EXPECT_EQ(u.kind, UltrasoundKind::capture);
  EXPECT_EQ(u.capture_source, (std::filesystem::path(example_scene_path("demo.yaml")).parent_path() / "frames/%04d.png")
                                  .lexically_normal()
                                  .string());
  EXPECT_EQ(u.clip_px[2], 640u);
  EXPECT_DOUBLE_EQ(u.pixel_spacing_m[1], 0.12e-3);
  // A device index stays an index; a clip of part pixels and a missing spacing are named.
  EXPECT_EQ(parse_scene(edited(edited(demo_text(), simulated, capture), "frames/%04d.png", "0"),
                        example_scene_path("demo.yaml"))
                .value()
                .devices.ultrasound.capture_source,
            "0");
  EXPECT_EQ(error_of(edited(edited(demo_text(), simulated, capture), "640", "640.5")).field,
            "devices.ultrasound.clip_px");
  EXPECT_EQ(error_of(edited(edited(demo_text(), simulated, capture), "\n    pixel_spacing_mm: [0.1, 0.12]", "")).field,
            "devices.ultrasound.pixel_spacing_mm");
}

TEST(StationScene, AnAprilTagTrackerReadsItsCameraIntrinsicsAndTags) {
  const std::string simulated =
      "    kind: simulated\n    rate_hz: 60\n    latency_ms: 10\n    position_noise_m: 0.00025\n    "
      "rotation_noise_rad: 0.001\n    seed: 1\n";
  const std::string apriltag =
      "    kind: apriltag\n    camera: frames/%04d.pgm\n    tag_size_m: 0.03\n    intrinsics: camera.txt\n"
      "    tags: {needle: 5, probe: 6, respiratory: 7}\n";
  const auto parsed = parse_scene(edited(demo_text(), simulated, apriltag), example_scene_path("demo.yaml"));
  ASSERT_TRUE(parsed.ok()) << parsed.error().describe();
  const TrackerSettings& t = parsed.value().devices.tracker;
  const std::filesystem::path folder = std::filesystem::path(example_scene_path("demo.yaml")).parent_path();
  EXPECT_EQ(t.camera_device, (folder / "frames/%04d.pgm").lexically_normal().string());
  EXPECT_EQ(t.camera_intrinsics_path, (folder / "camera.txt").lexically_normal().string());
  EXPECT_EQ(t.tag_ids.probe, 6u);
  // A device stays a device; a tag id beyond the family's 587 and two tools on one tag are named.
  EXPECT_EQ(parse_scene(edited(edited(demo_text(), simulated, apriltag), "frames/%04d.pgm", "/dev/video2"),
                        example_scene_path("demo.yaml"))
                .value()
                .devices.tracker.camera_device,
            "/dev/video2");
  EXPECT_EQ(error_of(edited(edited(demo_text(), simulated, apriltag), "probe: 6", "probe: 587")).field,
            "devices.tracker.tags.probe");
  EXPECT_EQ(error_of(edited(edited(demo_text(), simulated, apriltag), "probe: 6", "probe: 5")).field,
            "devices.tracker.tags");
  // A reference marker on a body of two tags is one of the tracker's tools, by its body alone.
  const std::string with_reference = edited(demo_text(), simulated,
                                            apriltag +
                                                "    tools: {reference: 9}\n"
                                                "    bodies: {reference: [{id: 20, xyz: [0, 0, 0], rpy: [0, 0, 0]}, "
                                                "{id: 21, xyz: [0.05, 0, 0], rpy: [0, 0, 0]}]}\n");
  const auto referenced = parse_scene(with_reference, example_scene_path("demo.yaml"));
  ASSERT_TRUE(referenced.ok()) << referenced.error().describe();
  const TrackerSettings& r = referenced.value().devices.tracker;
  const std::vector<ToolRole> roles = tool_roles(r.tools, r.tag_ids);
  ASSERT_EQ(roles.size(), 4u);
  EXPECT_STREQ(roles[3].role, "reference");
  EXPECT_EQ(r.tag_bodies.at("reference").size(), 2u);
}

TEST(StationScene, APlusRecordingsPixelSpacingIsReadAndChecked) {
  const std::string simulated =
      "  ultrasound:\n    kind: simulated\n    rate_hz: 20\n    target_noise_m: 0.001\n    seed: 2";
  const std::string plus = "  ultrasound:\n    kind: plus\n    recording: session.mha\n    pixel_spacing_mm: ";
  const auto parsed =
      parse_scene(edited(demo_text(), simulated, plus + "[0.08, 0.07]"), example_scene_path("demo.yaml"));
  ASSERT_TRUE(parsed.ok()) << parsed.error().describe();
  ASSERT_TRUE(parsed.value().devices.ultrasound.recording_pixel_spacing_m.has_value());
  EXPECT_DOUBLE_EQ((*parsed.value().devices.ultrasound.recording_pixel_spacing_m)[1], 0.07e-3);
  for (const char* bad : {"[0, 0.07]", "[0.08]", "[0.08, nan]", "fine"})
    EXPECT_EQ(
        error_of(edited(demo_text(), simulated, plus + bad)).field.rfind("devices.ultrasound.pixel_spacing_mm", 0), 0u)
        << bad;  // [i] for one entry
}

TEST(StationScene, TheOpenIgtlinkBridgeReadsItsAddressesAndNames) {
  const std::string with_bridge = demo_text() +
                                  "\nopenigtlink:\n  plus: {connect: 127.0.0.1:18946}\n"
                                  "  transforms: {NeedleToTracker: needle, ReferenceToTracker: respiratory}\n"
                                  "  image: Image_Reference\n";
  const auto parsed = parse_scene(with_bridge, example_scene_path("demo.yaml"));
  ASSERT_TRUE(parsed.ok()) << parsed.error().describe();
  const OpenIgtlinkSettings& bridge = *parsed.value().openigtlink;
  ASSERT_TRUE(bridge.plus.has_value());
  EXPECT_EQ(bridge.plus->port, 18946);
  EXPECT_FALSE(bridge.plus_connects);
  EXPECT_EQ(bridge.transforms,
            (std::map<std::string, std::string>{{"NeedleToTracker", "needle"}, {"ReferenceToTracker", "respiratory"}}));
  EXPECT_EQ(bridge.image, "Image_Reference");
  EXPECT_EQ(bridge.displays.host, "127.0.0.1");  // the default: Slicer's port, this host alone
  EXPECT_EQ(bridge.displays.port, 18944);
  EXPECT_FALSE(parse_scene(demo_text(), example_scene_path("demo.yaml")).value().openigtlink.has_value());
}

TEST(StationScene, TheOpenIgtlinkBridgeListensOnNamedAddressesOnly) {
  const std::string base = demo_text() + "\nopenigtlink:\n  plus: {connect: 127.0.0.1:18946}\n";
  const std::string plus = "  plus: {connect: 127.0.0.1:18946}";
  expect_error_in(base, plus, "  plus: {listen: 0.0.0.0:18946}", "openigtlink.plus.listen", "every interface");
  expect_error_in(base, plus, "  plus: {connect: plus.local:18946}", "openigtlink.plus.connect", "IPv4");
  expect_error_in(base, plus, "  plus: {connect: 127.0.0.1:0}", "openigtlink.plus.connect", "IPv4");
  expect_error_in(base, plus, "  plus: {connect: 127.0.0.1:1, listen: 127.0.0.1:2}", "openigtlink.plus", "either");
  expect_error_in(base, plus, "  displays: 10.0.0.1:70000", "openigtlink.displays", "a port");
  expect_error_in(base, plus, "  transforms: {StylusToTracker: scalpel}", "openigtlink.transforms.StylusToTracker",
                  "unknown role");
  expect_error_in(base, plus, "  transforms: {StylusToTracker: reference}", "openigtlink.transforms.StylusToTracker",
                  "reference when");
  expect_error_in(base, plus, "  transforms: {StylusToTracker: needle, StylusTipToTracker: needle}",
                  "openigtlink.transforms.StylusTipToTracker", "already StylusToTracker's");
  expect_error_in(base, plus, "  image: AVeryLongImageDeviceName", "openigtlink.image", "1 to 20");
}

TEST(StationScene, ARefusalsFlagIsHeldForTheScenesDeclaredTime) {
  EXPECT_EQ(parse_scene(demo_text(), example_scene_path("demo.yaml")).value().devices.clock.bad_sample_hold_ms, 2000.0);
  const std::string clock = "clock: {offset_ms: 0, max_ahead_ms: 50, max_behind_ms: 1000";
  EXPECT_EQ(
      parse_scene(edited(demo_text(), clock, clock + ", bad_sample_hold_ms: 500"), example_scene_path("demo.yaml"))
          .value()
          .devices.clock.bad_sample_hold_ms,
      500.0);
  EXPECT_EQ(error_of(edited(demo_text(), clock, clock + ", bad_sample_hold_ms: 0")).field,
            "devices.clock.bad_sample_hold_ms");
}

TEST(StationScene, TheIoThreadRunsBelowTheLoopsPriority) {
  EXPECT_EQ(parse_scene(demo_text(), example_scene_path("demo.yaml")).value().station.io_priority, 20);
  const std::string low = "realtime_priority: 10";
  EXPECT_EQ(parse_scene(edited(demo_text(), "realtime_priority: 80", low), example_scene_path("demo.yaml"))
                .value()
                .station.io_priority,
            9);
  EXPECT_EQ(parse_scene(edited(demo_text(), "realtime_priority: 80", "io_priority: 0"), example_scene_path("demo.yaml"))
                .value()
                .station.io_priority,
            0);
  EXPECT_EQ(error_of(edited(demo_text(), "realtime_priority: 80", "realtime_priority: 80\n  io_priority: 80")).field,
            "station.io_priority");
}

TEST(StationScene, UnknownKeysAreNamedWithTheirPath) {
  expect_error("  lock_memory: true", "  lock_memry: true", "station.lock_memry", "unknown key");
  expect_error("    cg_iterations: 3", "    cg_iteration: 3", "liver.model.cg_iteration", "unknown key");
  expect_error("topics:\n", "topic:\n", "topic", "unknown key");
}

TEST(StationScene, WrongTypesAreNamed) {
  expect_error("loop_rate_hz: 1000", "loop_rate_hz: fast", "station.loop_rate_hz", "expected a finite number");
  expect_error("element_count: 20", "element_count: 2.5", "needle.element_count", "expected an integer");
  expect_error("missing_compliance_radius_m: 0.015", "missing_compliance_radius_m: 0.5",
               "needle.missing_compliance_radius_m", "[0, 0.1]");
  expect_error("missing_compliance_radius_m: 0.015", "missing_compliance_radius_m: -0.01",
               "needle.missing_compliance_radius_m", "[0, 0.1]");
  expect_error("point_force_own_share: 0.5", "point_force_own_share: 0", "needle.point_force_own_share", "(0, 1]");
  expect_error("point_force_own_share: 0.5", "point_force_own_share: 1.5", "needle.point_force_own_share", "(0, 1]");
  expect_error("lock_memory: true", "lock_memory: maybe", "station.lock_memory", "expected true or false");
  expect_error("  name: demo", "  name: [a, b]", "station.name", "expected a single value");
  expect_error("  urdf: ../../../calibration/urdf/station.urdf", "  urdf: {path: x}", "frames.urdf",
               "expected a single value");
}

TEST(StationScene, OutOfRangeValuesAreNamed) {
  expect_error("loop_rate_hz: 1000", "loop_rate_hz: 2000", "station.loop_rate_hz", "outside (0, 1000]");
  expect_error("tissue_rate_hz: 100", "tissue_rate_hz: 1500", "station.tissue_rate_hz", "outside");
  expect_error("tissue_rate_hz: 100", "tissue_rate_hz: 300", "station.tissue_rate_hz", "must divide");
  expect_error("poisson_ratio: 0.45", "poisson_ratio: 0.5", "liver.material.poisson_ratio", "outside");
  expect_error("position_noise_m: 0.00025", "position_noise_m: .nan", "devices.tracker.position_noise_m", "finite");
  expect_error("cores: {realtime: 1, io: 0}", "cores: {realtime: 1, io: 1}", "station.cores.io", "must differ");
  expect_error("max_behind_ms: 1000}", "max_behind_ms: 0}", "devices.clock.max_behind_ms", "outside (0, 60000]");
  expect_error("max_ahead_ms: 50,", "max_ahead_ms: -1,", "devices.clock.max_ahead_ms", "outside");
  expect_error("max_speed_m_per_s: 2.0", "max_speed_m_per_s: 0", "devices.tracker.max_speed_m_per_s",
               "outside (0, 100]");
  expect_error("{surface: tumour, puncture_force_n: 2.0}",
               "{surface_point_m: [0, 0, 0], outward_normal: [0, 1], puncture_force_n: 2.0}",
               "needle.layers[1].outward_normal", "list of 3 numbers");
  expect_error("{surface: tumour, puncture_force_n: 2.0}", "{surface: tumour, region: 3, puncture_force_n: 2.0}",
               "needle.layers[1].region", "either surface or region");
  expect_error("{surface: tumour, puncture_force_n: 2.0}",
               "{surface: tumour, outward_normal: [0, 1, 0], puncture_force_n: 2.0}", "needle.layers[1].surface",
               "takes no surface_point_m or outward_normal");
  // A value each range allows but the needle's own validation refuses (bore wider than the tube).
  expect_error("inner_diameter_m: 0.00084", "inner_diameter_m: 0.002", "needle.inner_diameter_m", "");
}

TEST(StationScene, BadChoicesListTheAllowedOnes) {
  expect_error("rung: full", "rung: medium", "liver.model.rung", "'medium' is not one of full|reduced");
  expect_error("kind: simulated\n    rate_hz: 60", "kind: optical\n    rate_hz: 60", "devices.tracker.kind",
               "simulated|ndi|apriltag");
  expect_error("mesh: generated", "mesh: procedural", "liver.mesh", "expected 'generated'");
  expect_error("{surface: tumour,", "{surface: vessel,", "needle.layers[1].surface",
               "'vessel' is not one of capsule|tumour");
  expect_error("poses: nav/tool_pose", "poses: nav/tool pose", "topics.poses", "not a topic name");
  const std::string hung =
      edited(demo_text(), "devices:\n",
             "ligaments:\n  solver: banded_cholesky\n  blocks: [{footprint_centre_m: [0, 0]}]\ndevices:\n");
  expect_error_in(hung, "solver: banded_cholesky", "solver: lu", "ligaments.solver",
                  "'lu' is not one of banded_cholesky|cg_block_jacobi");
}

TEST(StationScene, TopicNamesAreReadCheckedAndEachOneIsOwn) {
  const std::string renamed = edited(demo_text(), "health: nav/station_health", "health: site_b/health");
  const auto scene = parse_scene(renamed, example_scene_path("demo.yaml"));
  ASSERT_TRUE(scene.ok()) << scene.error().describe();
  EXPECT_EQ(scene.value().topics.health, "site_b/health");
  EXPECT_EQ(scene.value().topics.needle_states, "nav/needle_state");
  expect_error("needle_states: nav/needle_state", "needle_states: 2nd/needle", "topics.needle_states",
               "not a topic name");
  // Two topics on one name: the later key is named, with the topic that has it already.
  expect_error("health: nav/station_health", "health: nav/target_prediction", "topics.health",
               "'nav/target_prediction' is already the name of topics.predictions");
}

TEST(StationScene, MissingRequiredKeysNameTheMapThatLacksThem) {
  const std::string no_rung = edited(demo_text(), "    rung: full\n", "");
  const Error rung = error_of(no_rung);
  EXPECT_EQ(rung.field, "liver.model.rung");
  EXPECT_EQ(rung.line, line_of(no_rung, "    law:"));  // where the map `model:` starts
  EXPECT_NE(rung.message.find("missing required key"), std::string::npos);
  const std::string no_io = edited(demo_text(), "cores: {realtime: 1, io: 0}", "cores: {realtime: 1}");
  EXPECT_EQ(error_of(no_io).field, "station.cores.io");
  EXPECT_EQ(error_of(no_io).line, line_of(no_io, "  cores:"));
  const std::string no_frames = edited(demo_text(), "frames:\n  urdf: ../../../calibration/urdf/station.urdf\n", "");
  EXPECT_EQ(error_of(no_frames).field, "frames");
  const std::string file_without_tumour =
      edited(demo_text(), "  mesh: generated ", "  mesh: {source: file, path: liver.vtu, unit: cm}");
  const Error tumour = error_of(file_without_tumour);
  EXPECT_EQ(tumour.field, "liver.tumour_m");
  EXPECT_EQ(tumour.line, line_of(file_without_tumour, "  mesh: {source"));
}

TEST(StationScene, RepeatedKeysAndSyntaxErrorsAreLocated) {
  expect_error("  lock_memory: true", "  loop_rate_hz: 500", "station.loop_rate_hz", "key given twice");
  const std::string broken = edited(demo_text(), "  cores: {realtime: 1, io: 0}", "  cores: {realtime: 1, io: 0");
  const Error syntax = error_of(broken);
  EXPECT_EQ(syntax.file, example_scene_path("demo.yaml"));
  EXPECT_GE(syntax.line, line_of(broken, "  cores:"));
  EXPECT_FALSE(syntax.message.empty());
  const Error scalar = error_of("just a line of text\n");
  EXPECT_EQ(scalar.field, "(document)");
  EXPECT_NE(scalar.message.find("expected a map"), std::string::npos);
}

/// An escalation block stating every key.
constexpr const char* kEscalationBlock =
    "    escalation:\n"
    "      rungs: [upper.navrb, ../top.navrb]\n"
    "      full_order_on_top: true\n"
    "      allowed: false\n"
    "      escalate_after_steps: 3\n"
    "      de_escalate_after_steps: 50\n"
    "      de_escalation_envelope_ratio: 0.8\n"
    "      de_escalation_residual: 0.1\n";

/// The demo scene with a reduced liver on the escalation ladder of kEscalationBlock.
const std::string& ladder_text() {
  static const std::string text =
      edited(demo_text(),
             "    rung: full\n    law: linear_elastic\n    rotation: corotational\n"
             "    integrator: implicit_euler\n    solver: ldlt_warped\n    cg_iterations: 3\n",
             std::string("    rung: reduced\n    artifact: lower.navrb\n    integrator: quasi_static\n"
                         "    envelope_factor: 2.0\n") +
                 kEscalationBlock);
  return text;
}

/// As expect_error_in, on ladder_text().
void expect_ladder_error(const std::string& from, const std::string& to, const std::string& field,
                         const std::string& word) {
  expect_error_in(ladder_text(), from, to, field, word);
}

TEST(StationScene, EscalationLadderReadsItsRungsAndOptions) {
  const auto parsed = parse_scene(ladder_text(), example_scene_path("demo.yaml"));
  ASSERT_TRUE(parsed.ok()) << parsed.error().describe();
  const LiverSettings& liver = parsed.value().liver;
  const std::filesystem::path folder = std::filesystem::path(example_scene_path("demo.yaml")).parent_path();
  EXPECT_EQ(liver.rung, LiverRung::reduced);
  EXPECT_EQ(liver.reduced_artifact_path, (folder / "lower.navrb").lexically_normal().string());
  ASSERT_TRUE(liver.escalation.has_value());
  const EscalationSettings& e = *liver.escalation;
  EXPECT_EQ(e.line, line_of(ladder_text(), "      rungs:"));  // where the map starts
  ASSERT_EQ(e.rungs.size(), 2u);
  EXPECT_EQ(e.rungs[0].artifact_path, (folder / "upper.navrb").lexically_normal().string());
  EXPECT_EQ(e.rungs[1].artifact_path, (folder / "../top.navrb").lexically_normal().string());
  EXPECT_EQ(e.rungs[1].line, line_of(ladder_text(), "      rungs:"));
  EXPECT_TRUE(e.full_order_on_top);
  EXPECT_FALSE(e.options.escalation_allowed);
  EXPECT_EQ(e.options.escalate_after_steps, 3);
  EXPECT_EQ(e.options.de_escalate_after_steps, 50);
  EXPECT_EQ(e.options.de_escalation_envelope_ratio, 0.8);
  EXPECT_EQ(e.options.de_escalation_residual, 0.1);
  EXPECT_EQ(liver.reduced.integrator, ReducedIntegrator::quasi_static);

  // Only `rungs` is required; one rung a line, the rest at the ladder's defaults.
  const std::string minimal =
      edited(ladder_text(), kEscalationBlock, "    escalation:\n      rungs:\n        - upper.navrb\n");
  const auto defaults = parse_scene(minimal, example_scene_path("demo.yaml"));
  ASSERT_TRUE(defaults.ok()) << defaults.error().describe();
  const EscalationSettings& d = *defaults.value().liver.escalation;
  ASSERT_EQ(d.rungs.size(), 1u);
  EXPECT_EQ(d.rungs[0].line, line_of(minimal, "        - upper.navrb"));
  EXPECT_FALSE(d.full_order_on_top);
  const ReducedLadderOptions ladder_defaults;
  EXPECT_EQ(d.options.escalation_allowed, ladder_defaults.escalation_allowed);
  EXPECT_TRUE(d.options.escalation_allowed);
  EXPECT_EQ(d.options.escalate_after_steps, 1);
  EXPECT_EQ(d.options.de_escalate_after_steps, 0);
  EXPECT_EQ(d.options.de_escalation_residual, ladder_defaults.de_escalation_residual);
  // Without the block there is no ladder.
  EXPECT_FALSE(parse_scene(demo_text(), example_scene_path("demo.yaml")).value().liver.escalation.has_value());
}

TEST(StationScene, EscalationErrorsNameTheirKeyPathAndLine) {
  expect_ladder_error("allowed: false", "allowed: sometimes", "liver.model.escalation.allowed",
                      "expected true or false");
  expect_ladder_error("allowed: false", "alowed: false", "liver.model.escalation.alowed", "unknown key");
  expect_ladder_error("escalate_after_steps: 3", "escalate_after_steps: 0",
                      "liver.model.escalation.escalate_after_steps", "outside [1, ");
  expect_ladder_error("de_escalate_after_steps: 50", "de_escalate_after_steps: -1",
                      "liver.model.escalation.de_escalate_after_steps", "outside [0, ");
  expect_ladder_error("rungs: [upper.navrb, ../top.navrb]", "rungs: []", "liver.model.escalation.rungs",
                      "expected a list of 1 to 8");
  expect_ladder_error("rungs: [upper.navrb, ../top.navrb]", "rungs: upper.navrb", "liver.model.escalation.rungs",
                      "expected a list");
  expect_ladder_error("rungs: [upper.navrb, ../top.navrb]", "rungs: [upper.navrb, {path: top.navrb}]",
                      "liver.model.escalation.rungs[1]", "expected a single value");
  expect_ladder_error("de_escalation_envelope_ratio: 0.8", "de_escalation_envelope_ratio: 2.5",
                      "liver.model.escalation.de_escalation_envelope_ratio", "below liver.model.envelope_factor");
  expect_ladder_error("de_escalation_residual: 0.1", "de_escalation_residual: 1.5",
                      "liver.model.escalation.de_escalation_residual", "outside [0, 1]");
  const std::string no_rungs = edited(ladder_text(), "      rungs: [upper.navrb, ../top.navrb]\n", "");
  EXPECT_EQ(error_of(no_rungs).field, "liver.model.escalation.rungs");
  EXPECT_NE(error_of(no_rungs).message.find("missing required key"), std::string::npos);
  // A full-order liver has no ladder: the block is an unknown key there.
  const std::string full_order =
      edited(demo_text(), "    cg_iterations: 3\n", "    cg_iterations: 3\n    escalation: {rungs: [a.navrb]}\n");
  const Error unknown = error_of(full_order);
  EXPECT_EQ(unknown.field, "liver.model.escalation");
  EXPECT_EQ(unknown.line, line_of(full_order, "    escalation:"));
  EXPECT_NE(unknown.message.find("unknown key"), std::string::npos) << unknown.describe();
}

TEST(StationScene, UnreadableAndOversizedFilesAreRefused) {
  const auto missing = load_scene("/nonexistent/scene.yaml");
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.error().file, "/nonexistent/scene.yaml");
  EXPECT_NE(missing.error().message.find("cannot open"), std::string::npos);
  const auto huge = parse_scene(std::string(kMaxSceneBytes + 1, '#'), "huge.yaml");
  ASSERT_FALSE(huge.ok());
  EXPECT_EQ(huge.error().file, "huge.yaml");
}

}  // namespace
}  // namespace nav::station
