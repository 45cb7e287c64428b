// navtool export end to end: a session recording of the demo scene (probe poses, a frame, the
// needle, the tumour now and ahead, three deformed surfaces) becomes VTK files and session.pvd,
// read back with VTK's own readers (python3-vtk9) and compared with what was recorded: the
// surface's points, triangles and displacements, the needle's polyline and tip force, the
// tumour's points and radii, the frame's pixels placed where the probe held it (the URDF's
// probe calibration, computed here), and the time series. A recording without a surface of the
// scene is refused.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "nav/calibration/frame_tree.hpp"
#include "nav/core/text_file.hpp"
#include "nav/dds/recording_file.hpp"
#include "nav/dds/sample_codec.hpp"
#include "nav/station/display_surface.hpp"
#include "nav/station/scene.hpp"
#include "nav/station/station_liver.hpp"
#include "scene_text.hpp"
#include "support/run_command.hpp"
#include "support/test_data.hpp"

namespace nav::station {
namespace {

using nav::testing::executable_path;
using nav::testing::run_command;
using nav::testing::temporary_path;

constexpr TimeNs kStartNs = 5 * kNsPerSecond;

template <typename Sample>
void append(dds::RecordingWriter& writer, const Sample& sample, TimeNs time_ns) {
  std::vector<std::uint8_t> bytes;
  ASSERT_TRUE(dds::encode_sample(sample, bytes));
  ASSERT_TRUE(writer.append(dds::topic_of<Sample>(), time_ns, time_ns, bytes).ok());
}

/// VTK's readers on every file of a folder's session.pvd, as JSON (python3-vtk9, Debian's
/// Python: /usr/bin/python3).
constexpr const char* kReadBack = R"(
import json, sys, os, xml.etree.ElementTree as ET
from vtkmodules.vtkIOXML import vtkXMLImageDataReader, vtkXMLPolyDataReader
def values(array):
    n = array.GetNumberOfComponents()
    return [list(array.GetTuple(i)) if n > 1 else array.GetTuple(i)[0] for i in range(array.GetNumberOfTuples())]
folder = sys.argv[1]
out = {"series": []}
for d in ET.parse(os.path.join(folder, "session.pvd")).getroot().iter("DataSet"):
    out["series"].append([float(d.get("timestep")), d.get("name"), d.get("file")])
    path = os.path.join(folder, d.get("file"))
    if path.endswith(".vti"):
        r = vtkXMLImageDataReader(); r.SetFileName(path); r.Update(); i = r.GetOutput()
        m = i.GetDirectionMatrix()
        world = [0.0, 0.0, 0.0]
        i.TransformIndexToPhysicalPoint(5, 7, 0, world)
        out[d.get("name")] = {"dims": list(i.GetDimensions()), "spacing": list(i.GetSpacing()),
            "direction": [m.GetElement(a, b) for a in range(3) for b in range(3)],
            "pixels": [int(v) for v in values(i.GetPointData().GetScalars())], "pixel_5_7_world": world}
    else:
        r = vtkXMLPolyDataReader(); r.SetFileName(path); r.Update(); p = r.GetOutput()
        data = p.GetPointData()
        arrays = {data.GetArrayName(k): values(data.GetArray(k)) for k in range(data.GetNumberOfArrays())}
        cell0 = [p.GetCell(0).GetPointId(k) for k in range(p.GetCell(0).GetNumberOfPoints())] if p.GetNumberOfCells() else []
        out[d.get("name")] = {"points": values(p.GetPoints().GetData()), "polys": p.GetNumberOfPolys(),
            "lines": p.GetNumberOfLines(), "verts": p.GetNumberOfVerts(), "cell0": cell0, "arrays": arrays}
print(json.dumps(out))
)";

TEST(NavtoolExport, ASessionOpensInVtkAsRecorded) {
  if (run_command("/usr/bin/python3 -c 'import vtkmodules.vtkIOXML' 2>&1").exit_code != 0) {
    if (nav::testing::running_under_ci()) GTEST_FAIL() << "python3-vtk9 missing under CI (toolchain/install-deps.sh)";
    GTEST_SKIP() << "python3-vtk9 is not installed: VTK's readers cannot check the files";
  }
  const std::string scene_path = nav::testing::example_scene_path("demo.yaml");
  auto scene = load_scene(scene_path);
  ASSERT_TRUE(scene.ok()) << scene.error().describe();
  auto mesh = make_station_mesh(scene.value());
  ASSERT_TRUE(mesh.ok());
  auto rest = make_display_surface(mesh.value());
  ASSERT_TRUE(rest.ok());

  const std::string recording = temporary_path("export_session.navrec");
  {
    auto writer = dds::RecordingWriter::create(recording);
    ASSERT_TRUE(writer.ok());
    Eigen::Isometry3d tracker_from_probe = Eigen::Isometry3d::Identity();
    tracker_from_probe.linear() = Eigen::AngleAxisd(0.6, Eigen::Vector3d(1, 2, 0).normalized()).toRotationMatrix();
    tracker_from_probe.translation() = Eigen::Vector3d(0.01, 0.12, 0.05);
    dds::ToolPose pose;
    pose.tool_id = scene.value().devices.tracker.tools.probe;
    const Eigen::Quaterniond q(tracker_from_probe.rotation());
    pose.orientation_wxyz = {q.w(), q.x(), q.y(), q.z()};
    pose.position_m = {0.01, 0.12, 0.05};
    pose.quality = 1.0f;
    for (const TimeNs at : {kStartNs - 10 * kNsPerMs, kStartNs + 10 * kNsPerMs}) {
      pose.source_time_ns = at;
      append(*writer.value(), pose, at);
    }
    auto frame = std::make_unique<dds::UltrasoundFrame>();
    frame->source_time_ns = kStartNs;
    frame->probe_tool_id = pose.tool_id;
    frame->width_px = 32;
    frame->height_px = 24;
    frame->pixel_spacing_m = {0.3e-3, 0.25e-3};
    frame->depth_m = 24 * 0.25e-3;
    for (std::size_t i = 0; i < frame->pixel_count(); ++i) frame->pixels[i] = static_cast<std::uint8_t>(7 * i + 3);
    append(*writer.value(), *frame, kStartNs);
    dds::NeedleState needle;
    needle.source_time_ns = kStartNs;
    needle.point_count = 4;
    for (std::size_t i = 0; i < 4; ++i) needle.shape_points_m[i] = {0.01 * i, 0.05, -0.02};
    needle.tip_force_n = {0.1, -0.2, 0.7};
    append(*writer.value(), needle, kStartNs);
    dds::TargetPrediction now, ahead;
    now.source_time_ns = ahead.source_time_ns = kStartNs;
    now.position_m = {-0.04, -0.005, 0.003};
    now.covariance_m2 = {4e-6, 0, 0, 0, 1e-6, 0, 0, 0, 1e-6};  // 2 mm along x
    ahead = now;
    ahead.horizon_ns = 50 * kNsPerMs;
    ahead.position_m = {-0.04, -0.005, 0.008};
    append(*writer.value(), now, kStartNs);
    append(*writer.value(), ahead, kStartNs);
    auto surface = std::make_unique<dds::DeformedSurface>();
    surface->surface_id = kLiverSurfaceId;
    surface->vertex_count = static_cast<std::uint32_t>(rest.value().rest_m.size());
    for (int step = 0; step < 3; ++step) {
      surface->source_time_ns = kStartNs + step * 40 * kNsPerMs;
      for (std::size_t i = 0; i < surface->vertex_count; ++i)
        for (std::size_t k = 0; k < 3; ++k)
          surface->vertex_positions_m[i][k] =
              static_cast<float>(rest.value().rest_m[i][k] + (k == 2 ? 0.001 * step : 0.0));
      append(*writer.value(), *surface, surface->source_time_ns);
    }
    ASSERT_TRUE(writer.value()->close().ok());

    // The image placement expected: no reference tool in the demo scene (the tracker is the
    // reference marker), the URDF's registration and probe calibration.
    auto frames = calibration::FrameTree::load(scene.value().frames.urdf_path);
    ASSERT_TRUE(frames.ok());
    const auto reference_from_model = frames.value().lookup("reference_marker", "liver_model", 0);
    const auto probe_from_image = frames.value().lookup("probe_marker", "image_plane", 0);
    ASSERT_TRUE(reference_from_model.ok() && probe_from_image.ok());
    const Eigen::Isometry3d model_from_image =
        reference_from_model.value().inverse() * tracker_from_probe * probe_from_image.value();

    const std::string out = temporary_path("export_session");
    const auto run = run_command(executable_path("navtool") + " export --recording " + recording + " --scene " +
                                 scene_path + " --out " + out + " 2>&1");
    ASSERT_EQ(run.exit_code, 0) << run.output;
    std::printf("%s", run.output.c_str());
    EXPECT_NE(run.output.find("3 display steps"), std::string::npos) << run.output;
    const std::string script = temporary_path("read_back.py");
    ASSERT_TRUE(nav::write_text_file(script, kReadBack).ok());
    const auto read = run_command("/usr/bin/python3 " + script + " " + out);
    ASSERT_EQ(read.exit_code, 0) << read.output;
    const auto vtk = nlohmann::json::parse(read.output, nullptr, false);
    ASSERT_FALSE(vtk.is_discarded()) << read.output;

    // The time series: three steps of four parts, 40 ms apart.
    ASSERT_EQ(vtk["series"].size(), 12u) << vtk["series"].dump();
    EXPECT_DOUBLE_EQ(vtk["series"][11][0].get<double>(), 0.08);
    // The last surface (its name's entry holds the last one read): the scene's triangles, 1 mm up.
    const auto& liver = vtk["liver_surface"];
    ASSERT_EQ(liver["points"].size(), rest.value().rest_m.size());
    EXPECT_EQ(liver["polys"].get<std::size_t>(), rest.value().triangles.size());
    EXPECT_EQ(liver["cell0"][1].get<int>(), rest.value().triangles[0][1]);
    EXPECT_NEAR(liver["points"][0][2].get<double>(), rest.value().rest_m[0][2] + 0.002, 1e-6);
    EXPECT_NEAR(liver["arrays"]["displacement_m"][0][2].get<double>(), 0.002, 1e-6);
    const auto& shaft = vtk["needle"];
    EXPECT_EQ(shaft["lines"].get<int>(), 1);
    EXPECT_EQ(shaft["cell0"].size(), 4u);
    EXPECT_NEAR(shaft["arrays"]["tip_force_n"][3][2].get<double>(), 0.7, 1e-6);
    EXPECT_NEAR(shaft["points"][3][0].get<double>(), 0.03, 1e-6);
    const auto& tumour = vtk["tumour"];
    EXPECT_EQ(tumour["verts"].get<int>(), 2);
    EXPECT_NEAR(tumour["arrays"]["sigma_radius_m"][0].get<double>(), 0.002, 1e-7);
    EXPECT_NEAR(tumour["arrays"]["horizon_s"][1].get<double>(), 0.05, 1e-7);
    EXPECT_NEAR(tumour["points"][1][2].get<double>(), 0.008, 1e-7);
    // The frame: its pixels, spacing and placement as VTK computes a pixel's place.
    const auto& image = vtk["ultrasound"];
    EXPECT_EQ(image["dims"], (std::vector<int>{32, 24, 1}));
    EXPECT_NEAR(image["spacing"][1].get<double>(), 0.25e-3, 1e-12);
    ASSERT_EQ(image["pixels"].size(), frame->pixel_count());
    EXPECT_EQ(image["pixels"][7 * 32 + 5].get<int>(), frame->pixels[7 * 32 + 5]);
    const Eigen::Vector3d expected = model_from_image * Eigen::Vector3d(5 * 0.3e-3, 7 * 0.25e-3, 0.0);
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(image["pixel_5_7_world"][k].get<double>(), expected[k], 1e-9) << "pixel (5, 7) axis " << k;
  }

  // A recording with no surface of the scene: refused, naming the topic.
  const std::string empty = temporary_path("export_empty.navrec");
  {
    auto writer = dds::RecordingWriter::create(empty);
    ASSERT_TRUE(writer.ok());
    dds::NeedleState needle;
    append(*writer.value(), needle, kStartNs);
    ASSERT_TRUE(writer.value()->close().ok());
  }
  const auto refused = run_command(executable_path("navtool") + " export --recording " + empty + " --scene " +
                                   scene_path + " --out " + temporary_path("export_empty") + " 2>&1");
  EXPECT_EQ(refused.exit_code, 2);
  EXPECT_NE(refused.output.find("deformed_surface"), std::string::npos) << refused.output;
}

}  // namespace
}  // namespace nav::station
