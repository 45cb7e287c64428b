#include "nav/bridge/igtl_bridge.hpp"

#include <cstdio>
#include <map>
#include <optional>
#include <thread>
#include <utility>
#include <vector>

#include "nav/bridge/igtl_inbound.hpp"
#include "nav/bridge/igtl_outbound.hpp"
#include "nav/dds/dds_node.hpp"
#include "nav/dds/sample_sink.hpp"
#include "nav/igtl/igtl_outputs.hpp"
#include "nav/igtl/igtl_stream.hpp"
#include "nav/igtl/wall_clock.hpp"
#include "nav/station/display_surface.hpp"
#include "nav/station/image_placement.hpp"
#include "nav/station/station_dds.hpp"
#include "nav/station/station_liver.hpp"

namespace nav::bridge {
namespace {

constexpr TimeNs kReadTimeoutNs = 100 * kNsPerMs;  // the inbound side looks at stop() this often
constexpr TimeNs kConnectTimeoutNs = kNsPerSecond;
constexpr TimeNs kReconnectEveryNs = kNsPerSecond;
constexpr int kLogLinesPerSecond = 10;         // refusals printed a second; the rest are counted
constexpr int kDisplayMessagesPerUpdate = 64;  // read (and dropped) from a display per update, at most
constexpr std::size_t kPosesPerUpdate = 1024;  // queued between two updates: 30 ms of four tools at 1 kHz, and more

/// Counters any thread may read.
struct Counters {
  std::atomic<std::uint64_t> poses_in{0}, frames_in{0}, skipped_in{0}, refused_in{0}, plus_connections{0},
      messages_out{0}, displays_connected{0}, displays_dropped{0}, refused_out{0}, images_unplaced{0};
};

/// Lines of a side of the bridge, at most kLogLinesPerSecond a second (one thread each).
class LogLimiter {
 public:
  explicit LogLimiter(const std::function<void(const std::string&)>& log) : log_(log) {}
  void line(const std::string& text) {
    const TimeNs now_ns = clock_.now_ns();
    if (now_ns >= second_ends_ns_) {
      if (suppressed_ > 0) log_(std::to_string(suppressed_) + " more refused in that second (counted)");
      second_ends_ns_ = now_ns + kNsPerSecond;
      lines_ = 0;
      suppressed_ = 0;
    }
    if (lines_++ < kLogLinesPerSecond)
      log_(text);
    else
      ++suppressed_;
  }

 private:
  const std::function<void(const std::string&)>& log_;
  MonotonicClock clock_;
  TimeNs second_ends_ns_ = 0;
  int lines_ = 0;
  std::uint64_t suppressed_ = 0;
};

igtl::Endpoint endpoint_of(const station::TcpAddress& address) { return {address.host, address.port}; }

}  // namespace

struct IgtlBridge::Impl {
  BridgeOptions options;
  TimeNs device_clock_offset_ns = 0;  // the scene's: device clock = monotonic clock - offset
  InboundConverter converter;
  OutboundPacker packer;
  station::ImagePlacement placement;
  std::optional<igtl::Endpoint> plus_server;    // the bridge connects to it
  std::optional<igtl::Listener> plus_listener;  // or a sender connects here
  igtl::Listener displays;
  Counters counters;
  std::unique_ptr<dds::UltrasoundFrame> frame = std::make_unique<dds::UltrasoundFrame>();
  // The sinks outlive the participant whose listeners fill them (declared first, destroyed last).
  std::unique_ptr<dds::LatestSink<dds::DeformedSurface>> surface =
      std::make_unique<dds::LatestSink<dds::DeformedSurface>>();
  std::unique_ptr<dds::LatestSink<dds::NeedleState>> needle = std::make_unique<dds::LatestSink<dds::NeedleState>>();
  std::unique_ptr<dds::RingSink<dds::TargetPrediction, 16>> predictions =
      std::make_unique<dds::RingSink<dds::TargetPrediction, 16>>();
  std::unique_ptr<dds::LatestSink<dds::StationHealth>> health = std::make_unique<dds::LatestSink<dds::StationHealth>>();
  std::unique_ptr<dds::LatestSink<dds::UltrasoundFrame>> frames =
      std::make_unique<dds::LatestSink<dds::UltrasoundFrame>>();
  std::unique_ptr<dds::RingSink<dds::ToolPose, kPosesPerUpdate>> poses =
      std::make_unique<dds::RingSink<dds::ToolPose, kPosesPerUpdate>>();
  std::unique_ptr<dds::DdsNode> devices;  // writes poses and frames
  std::unique_ptr<dds::DdsNode> display;  // reads the station's outputs

  Impl(BridgeOptions o, TimeNs offset_ns, InboundNames names, OutboundPacker p, station::ImagePlacement placed,
       igtl::Listener listener)
      : options(std::move(o)),
        device_clock_offset_ns(offset_ns),
        converter(std::move(names)),
        packer(std::move(p)),
        placement(std::move(placed)),
        displays(std::move(listener)) {}
};

IgtlBridge::IgtlBridge(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
IgtlBridge::~IgtlBridge() = default;

Result<std::unique_ptr<IgtlBridge>> IgtlBridge::open(const station::Scene& scene, BridgeOptions options) {
  if (!scene.openigtlink)
    return Error{.message = "the scene has no openigtlink section: the bridge has nothing to connect",
                 .file = scene.source_path,
                 .field = "openigtlink"};
  const station::OpenIgtlinkSettings& settings = *scene.openigtlink;
  const auto field_error = [&](const Error& error, const char* field) {
    return Error{.message = error.describe(), .file = scene.source_path, .line = settings.line, .field = field};
  };
  if (!options.log)
    options.log = [](const std::string& line) { std::fprintf(stderr, "navbridge igtl: %s\n", line.c_str()); };
  auto mesh = station::make_station_mesh(scene);
  if (!mesh) return mesh.error();
  auto surface = station::make_display_surface(mesh.value());
  if (!surface) return field_error(surface.error(), "liver.mesh");
  std::vector<std::array<std::uint32_t, 3>> triangles;
  triangles.reserve(surface.value().triangles.size());
  for (const auto& t : surface.value().triangles)
    triangles.push_back(
        {static_cast<std::uint32_t>(t[0]), static_cast<std::uint32_t>(t[1]), static_cast<std::uint32_t>(t[2])});
  auto placement = station::ImagePlacement::create(scene);
  if (!placement) return placement.error();
  auto displays = igtl::Listener::listen(endpoint_of(settings.displays));
  if (!displays) return field_error(displays.error(), "openigtlink.displays");
  auto impl = std::make_unique<Impl>(
      std::move(options), static_cast<TimeNs>(scene.devices.clock.offset_ms * 1e6), inbound_names(scene),
      OutboundPacker(std::move(triangles), static_cast<std::uint32_t>(surface.value().nodes.size())),
      std::move(placement).value(), std::move(displays).value());
  if (settings.plus && settings.plus_connects) {
    auto listener = igtl::Listener::listen(endpoint_of(*settings.plus));
    if (!listener) return field_error(listener.error(), "openigtlink.plus.listen");
    impl->plus_listener.emplace(std::move(listener).value());
  } else if (settings.plus) {
    impl->plus_server = endpoint_of(*settings.plus);
  }
  const dds::TopicNames names = station::topic_names(scene.topics);
  auto devices = station::make_station_node(scene.topics.domain_id, "navbridge_igtl_in", names, scene.network,
                                            station::Role::devices);
  if (!devices) return devices.error();
  impl->devices = std::move(devices).value();
  for (const Status& status :
       {impl->devices->advertise<dds::ToolPose>(), impl->devices->advertise<dds::UltrasoundFrame>()})
    if (!status) return status.error();
  auto display = station::make_station_node(scene.topics.domain_id, "navbridge_igtl_out", names, scene.network,
                                            station::Role::display);
  if (!display) return display.error();
  impl->display = std::move(display).value();
  for (const Status& status : {impl->display->subscribe(*impl->surface), impl->display->subscribe(*impl->needle),
                               impl->display->subscribe(*impl->predictions), impl->display->subscribe(*impl->health),
                               impl->display->subscribe(*impl->frames), impl->display->subscribe(*impl->poses)})
    if (!status) return status.error();
  return std::unique_ptr<IgtlBridge>(new IgtlBridge(std::move(impl)));
}

BridgeTotals IgtlBridge::totals() const noexcept {
  const Counters& c = impl_->counters;
  return {c.poses_in.load(),         c.frames_in.load(),      c.skipped_in.load(),         c.refused_in.load(),
          c.plus_connections.load(), c.messages_out.load(),   c.displays_connected.load(), c.displays_dropped.load(),
          c.refused_out.load(),      c.images_unplaced.load()};
}

int IgtlBridge::displays_port() const noexcept { return impl_->displays.port(); }

int IgtlBridge::plus_port() const noexcept { return impl_->plus_listener ? impl_->plus_listener->port() : 0; }

std::size_t IgtlBridge::readers_matched(dds::Topic topic) const { return impl_->devices->matched(topic); }

void IgtlBridge::run() {
  std::thread inbound([this] { run_inbound(); });
  run_outbound();
  inbound.join();
}

void IgtlBridge::run_inbound() {
  Impl& m = *impl_;
  if (!m.plus_server && !m.plus_listener) return;
  LogLimiter log(m.options.log);
  MonotonicClock clock;
  std::optional<igtl::MessageStream> stream;
  std::string waiting_said;  // the last "no PlusServer" line, said once until it changes
  Converted converted;
  while (!stopping_.load()) {
    if (!stream) {
      auto opened = m.plus_listener ? m.plus_listener->accept(kReadTimeoutNs)
                                    : igtl::MessageStream::connect(*m.plus_server, kConnectTimeoutNs);
      if (!opened) {
        if (m.plus_server && opened.error().describe() != waiting_said) {
          waiting_said = opened.error().describe();
          m.options.log("no PlusServer yet (" + waiting_said + "); trying again every second");
        }
        const TimeNs retry_ns = clock.now_ns() + (m.plus_server ? kReconnectEveryNs : 0);
        while (!stopping_.load() && clock.now_ns() < retry_ns) clock.sleep_until_ns(clock.now_ns() + kReadTimeoutNs);
        continue;
      }
      stream.emplace(std::move(opened).value());
      waiting_said.clear();
      m.counters.plus_connections.fetch_add(1);
      m.options.log("PlusServer connected: " + stream->peer());
    }
    auto message = stream->read(kReadTimeoutNs);
    if (!message) {
      // A refusal names its field; a stream closed was lost (or closed after a refused header);
      // anything else is a quiet spell.
      const bool refused = !message.error().field.empty();
      if (refused) {
        m.counters.refused_in.fetch_add(1);
        log.line("refused: " + message.error().describe());
      }
      if (!stream->open()) {
        m.options.log("PlusServer connection closed: " + stream->peer() +
                      (refused ? std::string() : " (" + message.error().message + ")"));
        stream.reset();
      }
      continue;
    }
    const TimeNs device_now_ns = clock.now_ns() - m.device_clock_offset_ns;
    m.converter.convert(message.value(), igtl::wall_now_ns(), device_now_ns, converted, *m.frame);
    for (Error& refused : converted.refused) {
      m.counters.refused_in.fetch_add(1);
      refused.file = stream->peer();
      log.line("refused: " + refused.describe());
    }
    m.counters.skipped_in.fetch_add(converted.skipped);
    for (const dds::ToolPose& pose : converted.poses) {
      if (m.devices->write(pose))
        m.counters.poses_in.fetch_add(1);
      else
        log.line("DDS did not take the pose of tool " + std::to_string(pose.tool_id));
    }
    if (converted.frame) {
      if (m.devices->write(*m.frame))
        m.counters.frames_in.fetch_add(1);
      else
        log.line("DDS did not take an ultrasound frame");
    }
  }
}

void IgtlBridge::run_outbound() {
  Impl& m = *impl_;
  LogLimiter log(m.options.log);
  MonotonicClock clock;
  const auto period_ns = static_cast<TimeNs>(1e9 / m.options.display_rate_hz);
  std::vector<igtl::MessageStream> displays;
  std::map<std::string, Packed> newest;  // by device name: what a display connecting now is sent first
  std::optional<dds::TargetPrediction> tumour_now, tumour_ahead;
  TimeNs next_ns = clock.now_ns();
  while (!stopping_.load()) {
    next_ns = std::max(next_ns + period_ns, clock.now_ns());
    std::vector<igtl::MessageStream> arrived;
    for (TimeNs wait_ns = next_ns - clock.now_ns(); !stopping_.load(); wait_ns = next_ns - clock.now_ns()) {
      auto client = m.displays.accept(std::max<TimeNs>(wait_ns, 0));
      if (!client) {
        if (wait_ns <= 0) break;
        continue;
      }
      m.counters.displays_connected.fetch_add(1);
      m.options.log("display connected: " + client.value().peer());
      arrived.push_back(std::move(client).value());
    }
    // Displays may send (Slicer's queries, its own transforms): read and drop, keeping streams in step.
    for (igtl::MessageStream& d : displays) {
      int taken = 0;
      for (auto got = d.read(0); (got || !got.error().field.empty()) && ++taken < kDisplayMessagesPerUpdate;
           got = d.read(0)) {
      }
    }

    const TimeNs wall_ns = igtl::wall_now_ns(), host_ns = clock.now_ns();
    const auto wall_of = [&](TimeNs source_ns) { return igtl::wall_stamp_ns(source_ns, wall_ns, host_ns); };
    std::vector<std::pair<std::string, Packed>> fresh;
    if (m.surface->update()) {
      auto packed = m.packer.surface(*m.surface->latest(), wall_of(m.surface->latest()->source_time_ns));
      if (packed) {
        fresh.emplace_back(igtl::kLiverSurfaceDevice, std::move(packed).value());
      } else {
        m.counters.refused_out.fetch_add(1);
        log.line("surface not sent: " + packed.error().describe());
      }
    }
    if (m.needle->update()) {
      std::vector<Packed> packed = m.packer.needle(*m.needle->latest(), wall_of(m.needle->latest()->source_time_ns));
      for (std::size_t i = 0; i < packed.size(); ++i)
        fresh.emplace_back(i == 0 ? igtl::kNeedleDevice : igtl::kNeedleTipDevice, std::move(packed[i]));
    }
    bool tumour_fresh = false;
    for (dds::TargetPrediction p; m.predictions->try_pop(p); tumour_fresh = true)
      (p.horizon_ns == 0 ? tumour_now : tumour_ahead) = p;
    if (tumour_fresh) {
      const TimeNs source_ns = tumour_now ? tumour_now->source_time_ns : tumour_ahead->source_time_ns;
      fresh.emplace_back(igtl::kTumourDevice,
                         m.packer.tumour(tumour_now ? &*tumour_now : nullptr, tumour_ahead ? &*tumour_ahead : nullptr,
                                         wall_of(source_ns)));
    }
    if (m.health->update())
      fresh.emplace_back(igtl::kHealthDevice,
                         m.packer.health(*m.health->latest(), wall_of(m.health->latest()->source_time_ns)));
    for (dds::ToolPose pose; m.poses->try_pop(pose);) m.placement.add_pose(pose);
    if (m.frames->update()) {
      const dds::UltrasoundFrame& frame = *m.frames->latest();
      // A frame's stamp is the devices' clock: the host's clock less the scene's offset.
      const TimeNs frame_wall_ns = wall_of(frame.source_time_ns + m.device_clock_offset_ns);
      if (const auto model_from_image = m.placement.model_from_image(frame.source_time_ns))
        fresh.emplace_back(igtl::kImageDevice, m.packer.image(frame, *model_from_image, frame_wall_ns));
      else
        m.counters.images_unplaced.fetch_add(1);
    }

    const auto send = [&](igtl::MessageStream& d, const Packed& message) {
      if (!d.open()) return;
      if (const Status sent = d.write(message); !sent) {
        log.line("display not taking messages: " + sent.error().describe());
        d.close();
        return;
      }
      m.counters.messages_out.fetch_add(1);
    };
    for (auto& [device, message] : fresh) {
      for (igtl::MessageStream& d : displays) send(d, message);
      newest[device] = std::move(message);
    }
    for (igtl::MessageStream& d : arrived) {
      for (const auto& [device, message] : newest) send(d, message);
      displays.push_back(std::move(d));
    }
    std::erase_if(displays, [&](const igtl::MessageStream& d) {
      if (d.open()) return false;
      m.counters.displays_dropped.fetch_add(1);
      m.options.log("display gone: " + d.peer());
      return true;
    });
  }
}

}  // namespace nav::bridge
