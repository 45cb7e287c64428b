// Writes the seeds of the urdf fuzz target into the folder given: the station URDF of
// calibration/urdf (copied from the source tree) and a calibrated variant.
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "fuzz/seed_generator.hpp"

bool write_fuzz_seeds(const std::filesystem::path& folder) {
  std::ifstream station(NAV_STATION_URDF);
  std::stringstream text;
  text << station.rdbuf();
  std::ofstream station_copy(folder / "station.urdf");
  station_copy << text.str();
  std::ofstream calibrated(folder / "calibrated.urdf");
  calibrated << "<robot name='r'><link name='a'/><link name='b'/><link name='c'/>"
                "<joint name='t' type='floating'><parent link='a'/><child link='b'/></joint>"
                "<joint name='j' type='fixed'><parent link='b'/><child link='c'/>"
                "<origin xyz='0.1 0 0.2' rpy='0 0.5 0' nav_calibrated='2026-11-21T12:00:00Z' nav_residual_m='2e-05'/>"
                "</joint></robot>";
  return static_cast<bool>(station) && static_cast<bool>(station_copy) && static_cast<bool>(calibrated);
}
