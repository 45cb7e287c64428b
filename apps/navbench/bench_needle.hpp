#pragma once
// navbench needle: step times of the flexible needle alone, with up to 32 constraint points,
// and coupled to the full-order corotational liver (about 5k tetrahedra), plus the force
// profile of an insertion-retraction cycle, as JSON records and an SVG plot. The scenes are
// inline here so that the Google Benchmark program (tests/benchmarks/bench_needle.cpp)
// measures the same ones.
#include <algorithm>
#include <string>
#include <vector>

#include "nav/needle/needle_step.hpp"
#include "nav/needle/needle_tissue_model.hpp"

namespace navbench {

/// navbench needle --json FILE [--quick]; returns the exit code.
int run_needle_bench(const std::vector<std::string>& args);

namespace needle_scenes {

/// The default 18 G steel needle, 15 cm, in `elements` Timoshenko elements, 1 kHz.
inline nav::NeedleParameters needle(int elements) {
  nav::NeedleParameters p;
  p.element_count = elements;
  return p;
}

/// A capsule (f_p 1 N) over parenchyma, facing the needle (along +x) 5 mm ahead of its tip,
/// and path points every `spacing_m` (up to 32).
inline nav::NeedleTissueScene capsule_and_parenchyma(double spacing_m) {
  nav::NeedleTissueScene scene;
  nav::TissueLayer capsule;
  capsule.surface_point_m = {0.155, 0.0, 0.0};
  capsule.outward_normal = {-1.0, 0.0, 0.0};
  capsule.puncture_force_n = 1.0;
  capsule.cutting_force_n = 0.3;
  capsule.friction_per_length_n_m = 15.0;
  nav::TissueLayer parenchyma = capsule;
  parenchyma.surface_point_m = {0.157, 0.0, 0.0};
  parenchyma.puncture_force_n = 0.2;
  parenchyma.cutting_force_n = 0.2;
  scene.layers = {capsule, parenchyma};
  scene.path_spacing_m = spacing_m;
  scene.max_path_points = 32;
  return scene;
}

/// Drives the base along +x to `x_m` at 20 mm/s (20 um per 1 ms tick).
inline void drive_base_to(const nav::NeedleTissueModel& model, nav::NeedleTissueData& data, double x_m) {
  nav::NeedleTissueInputs inputs;
  double x = data.needle.positions_m[0];
  while (x < x_m - 1e-12 || x > x_m + 1e-12) {
    x += std::max(-2e-5, std::min(2e-5, x_m - x));
    inputs.needle.base.position_m = {x, 0.0, 0.0};
    step(model, data, inputs);
  }
}

}  // namespace needle_scenes
}  // namespace navbench
