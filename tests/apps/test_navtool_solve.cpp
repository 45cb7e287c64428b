// navtool solve end to end: a column hanging under its own weight, given as a .vtu in
// centimetres, solved by the command for every law and read back with VTK's own reader
// (python3-vtk9): the supports carry the column's weight, the out-of-balance force is at the
// tolerance, the displacement is the library's and the free end sags as the analytic column
// does. Bad options are refused naming the option.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include <nlohmann/json.hpp>

#include "nav/mesh/vtu_writer.hpp"
#include "nav/tissue/static_equilibrium.hpp"
#include "support/run_command.hpp"
#include "support/test_data.hpp"
#include "tissue/tissue_test_support.hpp"

namespace nav {
namespace {

using nav::testing::executable_path;
using nav::testing::run_command;
using nav::testing::temporary_path;

/// VTK's reader on a .vtu: its counts and every point and cell array, as JSON.
constexpr const char* kReadBack = R"(
import json, sys
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader
r = vtkXMLUnstructuredGridReader(); r.SetFileName(sys.argv[1]); r.Update(); g = r.GetOutput()
def arrays(data):
    return {data.GetArrayName(k): [list(data.GetArray(k).GetTuple(i)) for i in range(data.GetArray(k).GetNumberOfTuples())]
            for k in range(data.GetNumberOfArrays())}
print(json.dumps({"points": g.GetNumberOfPoints(), "cells": g.GetNumberOfCells(),
                  "point_data": arrays(g.GetPointData()), "cell_data": arrays(g.GetCellData())}))
)";

constexpr double kLengthM = 0.1;
constexpr double kYoungsPa = 10'000.0;
constexpr double kDensityKgM3 = 100.0;  // a strain of 1 % at the top
constexpr double kGravityM_s2 = 9.81;

bool vtk_readers_available() {
  return run_command("/usr/bin/python3 -c 'import vtkmodules.vtkIOXML' 2>&1").exit_code == 0;
}

}  // namespace

TEST(NavtoolSolve, AHangingColumnOpensInVtkInEquilibrium) {
  if (!vtk_readers_available()) {
    if (nav::testing::running_under_ci()) GTEST_FAIL() << "python3-vtk9 missing under CI (toolchain/install-deps.sh)";
    GTEST_SKIP() << "python3-vtk9 is not installed: VTK's reader cannot check the file";
  }
  // The column in metres for the library, and in centimetres for the command.
  const TetMesh mesh = nav::testing::box_mesh({0.02, 0.02, kLengthM}, 0.005);
  TetMesh mesh_cm = mesh;
  for (Point3& node : mesh_cm.nodes_m)
    for (double& coordinate : node) coordinate *= 100.0;
  const std::string mesh_path = temporary_path("solve_column_cm.vtu");
  ASSERT_TRUE(write_vtu(mesh_path, mesh_cm).ok());
  const std::string script = temporary_path("solve_read_back.py");
  {
    std::FILE* file = std::fopen(script.c_str(), "w");
    ASSERT_NE(file, nullptr);
    std::fputs(kReadBack, file);
    std::fclose(file);
  }
  TissueScene scene;
  scene.default_material = {kYoungsPa, 0.0, kDensityKgM3};
  scene.gravity_m_s2 = {0.0, 0.0, -kGravityM_s2};
  scene.fixed_nodes = nav::testing::nodes_where(mesh, 2, kLengthM);
  const double weight_n = kDensityKgM3 * 0.02 * 0.02 * kLengthM * kGravityM_s2;
  const double analytic_sag_m = kDensityKgM3 * kGravityM_s2 * kLengthM * kLengthM / (2.0 * kYoungsPa);

  for (const char* model : {"linear", "corotational", "stvk", "neo-hookean"}) {
    SCOPED_TRACE(model);
    const std::string out = temporary_path(std::string("solve_column_") + model + ".vtu");
    const auto run =
        run_command(executable_path("navtool") + " solve --mesh " + mesh_path + " --unit cm --model " + model +
                    " --fix-box -1,-1,9.99,3,3,10.01 --gravity 0,0,-9.81" +
                    " --youngs-modulus-pa 10000 --poisson-ratio 0 --density-kg-m3 100 --out " + out + " 2>&1");
    std::printf("%s", run.output.c_str());
    ASSERT_EQ(run.exit_code, 0) << run.output;
    const auto read = run_command("/usr/bin/python3 " + script + " " + out + " 2>&1");
    ASSERT_EQ(read.exit_code, 0) << read.output;
    const auto vtu = nlohmann::json::parse(read.output);
    ASSERT_EQ(vtu["points"].get<std::size_t>(), mesh.nodes_m.size());
    ASSERT_EQ(vtu["cells"].get<std::size_t>(), mesh.tets.size());
    const auto& displacement = vtu["point_data"]["displacement_m"];
    const auto& out_of_balance = vtu["point_data"]["out_of_balance_force_n"];
    const auto& reaction = vtu["point_data"]["reaction_force_n"];
    ASSERT_EQ(vtu["cell_data"]["cauchy_stress_pa"].size(), mesh.tets.size());
    ASSERT_EQ(vtu["cell_data"]["cauchy_stress_pa"][0].size(), 6u);
    ASSERT_EQ(vtu["cell_data"]["von_mises_stress_pa"].size(), mesh.tets.size());

    const StaticLaw law = model == std::string("linear")         ? StaticLaw::linear
                          : model == std::string("corotational") ? StaticLaw::corotational
                          : model == std::string("stvk")         ? StaticLaw::st_venant_kirchhoff
                                                                 : StaticLaw::neo_hookean;
    const auto library = solve_static(mesh, scene, TissueInputs{}, law);
    ASSERT_TRUE(library.ok()) << library.error().describe();
    double reaction_z_n = 0.0, largest_out_of_balance_n = 0.0, difference_m = 0.0, free_end_sag_m = 0.0;
    for (std::size_t n = 0; n < mesh.nodes_m.size(); ++n) {
      reaction_z_n += reaction[n][2].get<double>();
      for (int c = 0; c < 3; ++c) {
        largest_out_of_balance_n = std::max(largest_out_of_balance_n, std::abs(out_of_balance[n][c].get<double>()));
        difference_m = std::max(difference_m,
                                std::abs(displacement[n][c].get<double>() - library.value().displacement_m[3 * n + c]));
      }
      if (mesh.nodes_m[n][2] == 0.0) free_end_sag_m = std::max(free_end_sag_m, -displacement[n][2].get<double>());
    }
    std::printf(
        "%s: supports carry %.6f N of the %.6f N weight, largest out-of-balance %.2e N, free end sags "
        "%.4f mm (analytic %.4f mm), %.1e m from the library's answer\n",
        model, reaction_z_n, weight_n, largest_out_of_balance_n, 1e3 * free_end_sag_m, 1e3 * analytic_sag_m,
        difference_m);
    EXPECT_NEAR(reaction_z_n, weight_n, 1e-5 * weight_n);
    EXPECT_LT(largest_out_of_balance_n, 1e-5 * weight_n);
    EXPECT_LT(difference_m, 1e-12);
    EXPECT_NEAR(free_end_sag_m, analytic_sag_m, 0.03 * analytic_sag_m);
  }
}

TEST(NavtoolSolve, RefusesBadOptionsNamingThem) {
  const std::string mesh_path = temporary_path("solve_refusals.vtu");
  ASSERT_TRUE(write_vtu(mesh_path, nav::testing::box_mesh({0.02, 0.02, 0.02}, 0.01)).ok());
  const std::string navtool =
      executable_path("navtool") + " solve --mesh " + mesh_path + " --out " + temporary_path("solve_refused.vtu");
  const std::pair<std::string, std::string> cases[] = {
      {" --model plastic --fix-box 0,0,0,1,1,0", "--model"},
      {" --model linear --fix-box 5,5,5,6,6,6", "--fix-box"},
      {" --model linear --fix-box 0,0,0,1", "--fix-box"},
      {" --model linear --fix-box 0,0,0,1,1,0 --gravity 0,x,0", "--gravity"},
      {" --model linear --fix-box 0,0,0,1,1,0 --force-nodes 99 --force-n 0,0,1", "--force-nodes"},
      {" --model linear --fix-box 0,0,0,1,1,0 --force-nodes 1", "--force-n"},
      {" --model linear --fix-box 0,0,0,1,1,0 --poisson-ratio 0.5", "poisson_ratio"},
  };
  for (const auto& [options, named] : cases) {
    const auto run = run_command(navtool + options + " 2>&1");
    EXPECT_EQ(run.exit_code, 2) << options << ": " << run.output;
    EXPECT_NE(run.output.find(named), std::string::npos) << options << ": " << run.output;
  }
}

}  // namespace nav
