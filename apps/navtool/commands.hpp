#pragma once
// The sub-commands of navtool. Each takes the arguments after its own name and returns
// the process exit code: 0 ok, 2 bad input (with a message on stderr), 1 other failure.
#include <string>
#include <vector>

namespace navtool {

constexpr int exit_ok = 0;
constexpr int exit_failure = 1;
constexpr int exit_bad_input = 2;

/// navtool mesh info FILE [--unit mm|cm|m] [--json]
int mesh_info(const std::vector<std::string>& args);

/// navtool mesh make (--liver | --surface FILE [--unit U] | --labels FILE) --size H --out FILE.vtu
int mesh_make(const std::vector<std::string>& args);

/// navtool record --out FILE [--duration-s S] [--domain D] ... and navtool replay FILE
/// [--as-fast-as-possible] [--domain D] ...: args start with "record" or "replay".
int record_replay(const std::vector<std::string>& args);

/// navtool evaluate (--scene FILE [--seconds S] [--domain D] | --recording FILE) [--settle-s S] [--plot F.svg] [--json
/// F]
int evaluate(const std::vector<std::string>& args);

/// navtool export --recording FILE.navrec --scene FILE --out DIR: a session as ParaView files.
int export_session(const std::vector<std::string>& args);

/// navtool solve --mesh FILE [--unit U] --model M --fix-box ... --out FILE.vtu: a static case to
/// equilibrium, with its displacement, stress and out-of-balance force (solve.cpp).
int solve(const std::vector<std::string>& args);

/// navtool reduce (--liver-dir DIR [--tets N] | --mesh FILE [--unit U]) --method M --r R
/// --force F [--samples M] [--seed S] [--load-scale S] --out FILE [--json], or --extend LOWER
/// instead of --method (the next rung of a ladder): see reduce.cpp.
int reduce(const std::vector<std::string>& args);

/// navtool security init DIR [--scene FILE] [--days N]: a test CA, the governance and every
/// role's identity and permissions for a scene's `security:` section (security_init.cpp).
int security_init(const std::vector<std::string>& args);

/// navtool calib pivot --poses FILE.csv [--tool NAME] [--urdf FILE [--out FILE] [--joint J]]
int calib_pivot(const std::vector<std::string>& args);

/// navtool calib handeye --marker-poses FILE.csv --camera-poses FILE.csv [--tool NAME] [--urdf ...]
int calib_handeye(const std::vector<std::string>& args);

/// navtool calib probe --recording F.mha --phantom DEVICESET.xml [--validation F.mha] [--urdf FILE ...]
int calib_probe(const std::vector<std::string>& args);

/// navtool calib temporal --video F.mha --tracker F.mha [--max-lag-s S] [--out FILE]
int calib_temporal(const std::vector<std::string>& args);

/// navtool calib register --model-points F --tracked-points F [--surface F --unit U --surface-points F] [--urdf ...]
int calib_register(const std::vector<std::string>& args);

/// navtool calib camera --images DIR --tag-size S --pitch P --cols C --rows R --out FILE
int calib_camera(const std::vector<std::string>& args);

}  // namespace navtool
