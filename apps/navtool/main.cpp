// navtool: offline tools around the library (mesh inspection and meshing for now).
#include <cstdio>
#include <string>
#include <vector>

#include "commands.hpp"

namespace {

constexpr const char* kUsage =
    "usage:\n"
    "  navtool mesh info FILE [--unit mm|cm|m] [--json]\n"
    "  navtool mesh make (--liver | --surface FILE [--unit mm|cm|m] | --labels FILE) --size H_M --out FILE.vtu\n"
    "  navtool record --out FILE [--duration-s S] [--scene FILE] [--domain D] [--local-address A] [--peer A]...\n"
    "  navtool replay FILE [--as-fast-as-possible] [--scene FILE] [--domain D] [--local-address A] [--peer A]...\n"
    "  navtool evaluate (--scene FILE [--seconds S] [--domain D] | --recording FILE.navrec) [--settle-s S] [--plot "
    "F.svg] [--json F]\n"
    "  navtool export --recording FILE.navrec --scene FILE --out DIR   (the session as ParaView files, session.pvd)\n"
    "  navtool solve --mesh FILE [--unit mm|cm|m] --model linear|corotational|stvk|neo-hookean --fix-box "
    "X0,Y0,Z0,X1,Y1,Z1\n"
    "                [--gravity GX,GY,GZ] [--force-nodes I,J,... --force-n FX,FY,FZ] [--youngs-modulus-pa E]\n"
    "                [--poisson-ratio NU] [--density-kg-m3 RHO] [--tolerance T] --out FILE.vtu   (a static case)\n"
    "  navtool reduce (--liver-dir DIR [--tets N] | --mesh FILE [--unit U]) --method modes|modal-derivatives|pod\n"
    "                 --r R --force linear|corotational|stvk|stvk-cubic [--samples M] [--seed S] --out FILE [--json]\n"
    "  navtool reduce (--liver-dir DIR [--tets N] | --mesh FILE [--unit U]) --extend LOWER.navrb --r R\n"
    "                 [--load-scale S] [--samples M] [--seed S] --out FILE [--json]   (the next rung of a ladder)\n"
    "  navtool calib pivot (--poses FILE.csv | --recording FILE.navrec) [--tool NAME|ID] [--urdf FILE [--out FILE] "
    "[--joint J]]\n"
    "  navtool calib handeye --marker-poses FILE.csv --camera-poses FILE.csv [--tool NAME] [--urdf FILE ...]\n"
    "  navtool calib register --model-points F.csv --tracked-points F.csv [--surface F --unit U --surface-points "
    "F.csv]\n"
    "                         [--urdf FILE ...]\n"
    "  navtool calib camera --images DIR --tag-size S_M --pitch P_M --cols C --rows R --out FILE [--k3 0|1]\n"
    "  navtool calib probe --recording F.mha --phantom DEVICESET.xml [--validation F.mha] [--probe T] [--reference T]\n"
    "                      [--min-frames N] [--urdf FILE [--out FILE] [--joint J]]\n"
    "  navtool calib temporal --video F.mha --tracker F.mha [--probe T] [--reference T] [--max-lag-s S] [--out FILE]\n"
    "  navtool security init DIR [--scene FILE] [--days N]   (a test CA and the identities of a secured station)\n";

}  // namespace

int main(int argc, char** argv) {
  const std::vector<std::string> args(argv + 1, argv + argc);
  if (args.size() >= 2 && args[0] == "mesh") {
    const std::vector<std::string> rest(args.begin() + 2, args.end());
    if (args[1] == "info") return navtool::mesh_info(rest);
    if (args[1] == "make") return navtool::mesh_make(rest);
  }
  if (!args.empty() && args[0] == "reduce") return navtool::reduce({args.begin() + 1, args.end()});
  if (!args.empty() && (args[0] == "record" || args[0] == "replay")) return navtool::record_replay(args);
  if (!args.empty() && args[0] == "evaluate") return navtool::evaluate(args);
  if (!args.empty() && args[0] == "solve") return navtool::solve({args.begin() + 1, args.end()});
  if (!args.empty() && args[0] == "export") return navtool::export_session({args.begin() + 1, args.end()});
  if (args.size() >= 2 && args[0] == "security" && args[1] == "init")
    return navtool::security_init({args.begin() + 2, args.end()});
  if (args.size() >= 2 && args[0] == "calib") {
    const std::vector<std::string> calib_args(args.begin() + 2, args.end());
    if (args[1] == "pivot") return navtool::calib_pivot(calib_args);
    if (args[1] == "handeye") return navtool::calib_handeye(calib_args);
    if (args[1] == "register") return navtool::calib_register(calib_args);
    if (args[1] == "camera") return navtool::calib_camera(calib_args);
    if (args[1] == "probe") return navtool::calib_probe(calib_args);
    if (args[1] == "temporal") return navtool::calib_temporal(calib_args);
  }
  std::fputs(kUsage, stderr);
  return navtool::exit_bad_input;
}
