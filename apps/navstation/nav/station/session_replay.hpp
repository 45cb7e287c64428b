#pragma once
// A recorded session replayed through the station: the tracker's poses and the scanner's
// frames of a recording (navtool record of a live session) become the loop's samples, each
// frame the tumour point the station's observer finds in it (on the frame's own grid), and the
// loop runs on a SimulatedClock at its period from the first sample. The same recording gives
// the same outputs bit for bit (their hash is printed). Every sample meets the live station's
// boundary (SampleBoundary: content, stamp against its recorded arrival, stream order; the
// PoseInbox's tools, pose bounds and per-tool order): records that do not decode or are
// refused are counted by reason and left out; a damaged recording plays its intact part.
// Init/report-time code.
#include <cstdint>
#include <optional>
#include <string>

#include "nav/core/error.hpp"
#include "nav/dds/samples.hpp"
#include "nav/station/scene.hpp"
#include "nav/station/station_run.hpp"

namespace nav::station {

/// What a replay of a recorded session did.
struct SessionReplay {
  StationReplay replay;                ///< the ticks and the hash of their outputs
  std::int64_t poses = 0, frames = 0;  ///< taken from the recording
  std::int64_t records_refused = 0;    ///< poses and frames unreadable, or refused at the station's boundary
  dds::BoundaryCounts boundary{};      ///< the boundary's verdicts on the recorded poses and frames, as live
  ObserverCounts observer;             ///< the frames and the tumour points found in them
  std::optional<Error> damage;         ///< where the recording is damaged (its intact part played)
  TimeNs duration_ns = 0;              ///< from the first to the last recorded sample's arrival
};

/// Replays the poses and frames of the recording at `path` through the station of `scene`.
Result<SessionReplay> replay_session(const Scene& scene, const std::string& path);

/// The printed summary of a replay.
std::string format_replay(const Scene& scene, const std::string& path, const SessionReplay& replay);

}  // namespace nav::station
