// Writes the seeds of the scene fuzz target into the folder given: variants of the example
// scenes (apps/navstation/scenes, which the target also takes as seeds) that reach the
// sections and kinds those leave out: ligaments, the reduced rung on a mesh file, the NDI
// and AprilTag trackers, PLUS playback, anchors and aliases, a deeply nested value (yaml-cpp's
// depth guard) and a few broken scenes.
#include <filesystem>
#include <fstream>
#include <string>

#include "fuzz/seed_generator.hpp"

namespace {

constexpr const char* kHead =
    "station:\n  name: seed\n  loop_rate_hz: 500\n  tissue_rate_hz: 50\n  display_latency_ms: 30\n"
    "  cores: {realtime: 1, io: 0}\n  realtime_priority: 60\n  lock_memory: false\n"
    "frames: {urdf: station.urdf}\n";

constexpr const char* kSimulatedDevices =
    "devices:\n  tracker: {kind: simulated, rate_hz: 40, dropout_probability: 0.1, seed: 7}\n"
    "  ultrasound: {kind: simulated, rate_hz: 15}\n";

const struct {
  const char* name;
  std::string text;
} kSeeds[] = {
    {"ligaments.yaml",
     std::string(kHead) +
         "liver:\n  mesh: {source: generated, element_size_m: 0.015}\n"
         "  model: {rung: full, law: st_venant_kirchhoff, integrator: quasi_static, solver: cg_block_jacobi,"
         " cg_iterations: 40, incompressibility_gain_pa: 1000}\n"
         "ligaments:\n  rayleigh_mass_per_s: 2\n  blocks:\n"
         "    - {footprint_centre_m: [-0.045, 0.0], width_m: 0.02, frames: [3, 4, 3], embed_m: 0.006}\n" +
         kSimulatedDevices},
    {"reduced_file.yaml",
     std::string(kHead) +
         "liver:\n  mesh:\n    source: file\n    path: /data/liver.vtu\n    unit: mm\n"
         "  material: {youngs_modulus_pa: 3000}\n"
         "  model: {rung: reduced, artifact: liver.navrb, integrator: quasi_static, newton_iterations: 3,"
         " frozen_tangent: false, envelope_factor: 2}\n  tumour_m: [0.01, 0.02, -0.03]\n"
         "devices:\n  tracker: {kind: ndi, serial: /dev/ttyUSB0}\n"
         "  ultrasound: {kind: plus, recording: sweep.igs.mha}\n"
         "topics: {domain_id: 12, poses: a/poses, images: a/images, predictions: a/pred, surfaces: a/surf}\n"},
    {"apriltag.yaml", std::string(kHead) +
                          "liver: &organ\n  mesh: generated\n  model: {rung: full, law: linear_elastic, rotation: none,"
                          " integrator: explicit_central_difference}\n"
                          "needle: {length_m: 0.2, theory: euler_bernoulli, element_count: 10, bevel_steering: true,"
                          " layers: [{surface_point_m: [0, 0, 0.05], outward_normal: [0, 0, 2]}]}\n"
                          "devices:\n  tracker: {kind: apriltag, camera: /dev/video0, tag_size_m: 0.03}\n"
                          "  ultrasound: {kind: simulated}\n"},
    {"ndi_tcp.yaml",
     std::string(kHead) +
         "liver:\n  mesh: generated\n  model: {rung: full, law: linear_elastic, integrator: implicit_euler}\n"
         "devices:\n  tracker: {kind: ndi, host: 10.0.0.2, port: 8765}\n  ultrasound: {kind: simulated}\n"},
    {"duplicate_key.yaml", std::string(kHead) + "station: {name: twice}\n"},
    {"unknown_section.yaml", std::string(kHead) + "camera: {fps: 30}\n"},
    {"aliases.yaml", "a: &a [1, 2]\nb: &b [*a, *a, *a]\nstation: {name: *b, <<: *a}\n"},
    {"deep_nesting.yaml", "station: " + std::string(3000, '[') + std::string(3000, ']') + "\n"},
};

}  // namespace

bool write_fuzz_seeds(const std::filesystem::path& folder) {
  bool written = true;
  for (const auto& seed : kSeeds) {
    std::ofstream file(folder / seed.name);
    file << seed.text;
    written = written && static_cast<bool>(file);
  }
  return written;
}
