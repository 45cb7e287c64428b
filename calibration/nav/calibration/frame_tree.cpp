#include "nav/calibration/frame_tree.hpp"

#include <console_bridge/console.h>
#include <tinyxml2.h>
#include <urdf_parser/urdf_parser.h>

#include <algorithm>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

namespace nav::calibration {
namespace {

Error xml_error(const std::string& path, const tinyxml2::XMLElement* element, const std::string& field,
                const std::string& message) {
  return Error{
      .message = message, .file = path, .line = element != nullptr ? element->GetLineNum() : 0, .field = field};
}

/// Reads "a b c" into three finite numbers.
bool parse_triple(const char* text, Eigen::Vector3d& out) {
  std::istringstream stream(text);
  stream >> out.x() >> out.y() >> out.z();
  std::string rest;
  return !stream.fail() && !(stream >> rest) && out.allFinite();
}

/// Checks that links and joints form one tree: unique names, joints between declared links, every
/// link the child of at most one joint, no cycle, a single root. urdfdom rejects such graphs too,
/// but without saying where, and a cyclic one leaks inside it.
Status check_topology(const tinyxml2::XMLElement& robot, const std::string& path) {
  std::map<std::string, const tinyxml2::XMLElement*> links;
  for (const auto* link = robot.FirstChildElement("link"); link; link = link->NextSiblingElement("link")) {
    if (!links.emplace(link->Attribute("name"), link).second) {
      return xml_error(path, link, std::string("link ") + link->Attribute("name"), "duplicate link name");
    }
  }
  std::map<std::string, std::string> parent_of;
  std::set<std::string> joint_names;
  for (const auto* joint = robot.FirstChildElement("joint"); joint; joint = joint->NextSiblingElement("joint")) {
    const std::string field = std::string("joint ") + joint->Attribute("name");
    if (!joint_names.insert(joint->Attribute("name")).second)
      return xml_error(path, joint, field, "duplicate joint name");
    const std::string parent = joint->FirstChildElement("parent")->Attribute("link");
    const std::string child = joint->FirstChildElement("child")->Attribute("link");
    for (const std::string& end : {parent, child}) {
      if (links.count(end) == 0) return xml_error(path, joint, field, "no <link name=\"" + end + "\">");
    }
    if (!parent_of.emplace(child, parent).second) {
      return xml_error(path, joint, field, "link " + child + " is already the child of another joint");
    }
  }
  std::size_t roots = 0;
  for (const auto& [name, element] : links) {
    if (parent_of.count(name) == 0) {
      ++roots;
      continue;
    }
    std::string ancestor = name;
    for (std::size_t depth = 0; parent_of.count(ancestor) != 0; ++depth) {
      if (depth > links.size())
        return xml_error(path, element, "link " + name, "the joints form a cycle through this link");
      ancestor = parent_of.at(ancestor);
    }
  }
  if (roots != 1) {
    return xml_error(path, &robot, "robot",
                     "the links form " + std::to_string(roots) + " trees; a station has one root");
  }
  return Done{};
}

/// Checks what urdfdom only reports on its console: every link and joint is complete, joint
/// types are those a station has, origins are numbers.
Status check_elements(const tinyxml2::XMLDocument& document, const std::string& path) {
  const tinyxml2::XMLElement* robot = document.FirstChildElement("robot");
  if (robot == nullptr) return xml_error(path, document.RootElement(), "robot", "no <robot> element");
  for (const auto* link = robot->FirstChildElement("link"); link; link = link->NextSiblingElement("link")) {
    if (link->Attribute("name") == nullptr) return xml_error(path, link, "link", "<link> without a name");
  }
  for (const auto* joint = robot->FirstChildElement("joint"); joint; joint = joint->NextSiblingElement("joint")) {
    const char* name = joint->Attribute("name");
    if (name == nullptr) return xml_error(path, joint, "joint", "<joint> without a name");
    const std::string field = std::string("joint ") + name;
    const char* type = joint->Attribute("type");
    if (type == nullptr || (std::string(type) != "fixed" && std::string(type) != "floating")) {
      return xml_error(path, joint, field, "type must be fixed (calibrated) or floating (tracked)");
    }
    for (const char* end : {"parent", "child"}) {
      const auto* element = joint->FirstChildElement(end);
      if (element == nullptr || element->Attribute("link") == nullptr) {
        return xml_error(path, joint, field, std::string("missing <") + end + " link=...>");
      }
    }
    if (const auto* origin = joint->FirstChildElement("origin")) {
      for (const char* attribute : {"xyz", "rpy"}) {
        Eigen::Vector3d values;
        const char* text = origin->Attribute(attribute);
        if (text != nullptr && !parse_triple(text, values)) {
          return xml_error(path, origin, field + " origin " + attribute, "expected three numbers");
        }
      }
    }
  }
  return check_topology(*robot, path);
}

Transform to_transform(const urdf::Pose& pose) {
  const Eigen::Quaterniond q(pose.rotation.w, pose.rotation.x, pose.rotation.y, pose.rotation.z);
  return make_transform(q, {pose.position.x, pose.position.y, pose.position.z});
}

std::string format_triple(const Eigen::Vector3d& v) {
  char text[96];
  std::snprintf(text, sizeof text, "%.17g %.17g %.17g", v.x(), v.y(), v.z());
  return text;
}

}  // namespace

std::string utc_timestamp() {
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &utc);
  return text;
}

Result<FrameTree> FrameTree::load(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) return Error{.message = "cannot open the URDF file", .file = path};
  std::ostringstream text;
  text << file.rdbuf();
  return parse(text.str(), path);
}

Result<FrameTree> FrameTree::parse(const std::string& xml, const std::string& path) {
  tinyxml2::XMLDocument document;
  if (document.Parse(xml.c_str(), xml.size()) != tinyxml2::XML_SUCCESS) {
    return Error{
        .message = std::string("not XML: ") + document.ErrorStr(), .file = path, .line = document.ErrorLineNum()};
  }
  if (Status checked = check_elements(document, path); !checked) return checked.error();
  console_bridge::setLogLevel(console_bridge::CONSOLE_BRIDGE_LOG_NONE);
  // urdfdom reads the <robot> element exactly as checked above, printed back by tinyxml2: its own
  // XML parser would read malformed text differently and could meet a graph we never saw.
  tinyxml2::XMLPrinter checked_robot;
  document.FirstChildElement("robot")->Accept(&checked_robot);
  const urdf::ModelInterfaceSharedPtr model = urdf::parseURDF(checked_robot.CStr());
  if (!model || !model->getRoot()) {
    return Error{.message = "urdfdom rejected the model (unknown link, duplicate name, several roots or a cycle)",
                 .file = path,
                 .field = "robot"};
  }
  FrameTree tree;
  tree.source_path_ = path;
  tree.xml_ = xml;
  tree.root_ = model->getRoot()->name;
  for (const auto& [name, joint] : model->joints_) {
    FrameJoint frame_joint{name,
                           joint->parent_link_name,
                           joint->child_link_name,
                           joint->type == urdf::Joint::FLOATING,
                           to_transform(joint->parent_to_joint_origin_transform),
                           std::nullopt};
    tree.joint_of_child_[frame_joint.child] = name;
    tree.joints_[name] = std::move(frame_joint);
  }
  for (const auto* joint = document.FirstChildElement("robot")->FirstChildElement("joint"); joint;
       joint = joint->NextSiblingElement("joint")) {
    const auto* origin = joint->FirstChildElement("origin");
    if (origin == nullptr || origin->Attribute("nav_calibrated") == nullptr) continue;
    tree.joints_[joint->Attribute("name")].record =
        CalibrationRecord{origin->Attribute("nav_calibrated"), origin->DoubleAttribute("nav_residual_m", 0.0)};
  }
  return tree;
}

std::vector<std::string> FrameTree::frames() const {
  std::vector<std::string> names{root_};
  for (const auto& [name, joint] : joints_) names.push_back(joint.child);
  std::sort(names.begin(), names.end());
  return names;
}

const FrameJoint* FrameTree::joint(const std::string& name) const {
  const auto found = joints_.find(name);
  return found == joints_.end() ? nullptr : &found->second;
}

Status FrameTree::add_pose(const std::string& frame, TimeNs time_ns, const Transform& parent_from_child) {
  const auto found = joint_of_child_.find(frame);
  if (found == joint_of_child_.end() || !joints_.at(found->second).tracked) {
    return Error{.message = "no floating joint has this child frame", .file = source_path_, .field = frame};
  }
  auto& poses = history_[frame];
  if (!poses.empty() && time_ns <= poses.back().time_ns) {
    return Error{.message = "pose time does not increase", .file = source_path_, .field = frame};
  }
  poses.push_back({time_ns, parent_from_child});
  if (poses.size() > kPoseHistory) poses.pop_front();
  return Done{};
}

Result<Transform> FrameTree::joint_transform(const FrameJoint& joint, TimeNs time_ns) const {
  if (!joint.tracked) return joint.parent_from_child;
  const auto found = history_.find(joint.child);
  if (found == history_.end() || found->second.empty()) {
    return Error{.message = "no tracked pose buffered", .file = source_path_, .field = joint.child};
  }
  const auto& poses = found->second;
  if (time_ns < poses.front().time_ns || time_ns > poses.back().time_ns) {
    return Error{.message = "time " + std::to_string(time_ns) + " ns outside the buffered span [" +
                            std::to_string(poses.front().time_ns) + ", " + std::to_string(poses.back().time_ns) +
                            "] ns",
                 .file = source_path_,
                 .field = joint.child};
  }
  const auto after = std::lower_bound(poses.begin(), poses.end(), time_ns,
                                      [](const TimedPose& pose, TimeNs t) { return pose.time_ns < t; });
  if (after->time_ns == time_ns) return after->parent_from_child;
  const auto before = after - 1;
  const double alpha =
      static_cast<double>(time_ns - before->time_ns) / static_cast<double>(after->time_ns - before->time_ns);
  return interpolate(before->parent_from_child, after->parent_from_child, alpha);
}

std::vector<std::string> FrameTree::path_to_root(const std::string& frame) const {
  std::vector<std::string> path{frame};
  while (path.back() != root_) {
    const auto found = joint_of_child_.find(path.back());
    if (found == joint_of_child_.end()) return {};
    path.push_back(joints_.at(found->second).parent);
  }
  return path;
}

Result<Transform> FrameTree::ancestor_from_frame(const std::vector<std::string>& path, std::size_t ancestor_index,
                                                 TimeNs time_ns) const {
  Transform ancestor_from = Transform::Identity();
  for (std::size_t i = 0; i < ancestor_index; ++i) {
    Result<Transform> step = joint_transform(joints_.at(joint_of_child_.at(path[i])), time_ns);
    if (!step) return step.error();
    ancestor_from = step.value() * ancestor_from;
  }
  return ancestor_from;
}

Result<Transform> FrameTree::lookup(const std::string& target, const std::string& source, TimeNs time_ns) const {
  // Only the joints below the frames' lowest common ancestor take part, so that a tracked
  // joint above both (e.g. the needle marker for base -> tip) needs no pose.
  const std::vector<std::string> target_path = path_to_root(target);
  if (target_path.empty()) return Error{.message = "unknown frame", .file = source_path_, .field = target};
  const std::vector<std::string> source_path = path_to_root(source);
  if (source_path.empty()) return Error{.message = "unknown frame", .file = source_path_, .field = source};
  std::size_t target_index = target_path.size() - 1;
  std::size_t source_index = source_path.size() - 1;
  while (target_index > 0 && source_index > 0 && target_path[target_index - 1] == source_path[source_index - 1]) {
    --target_index;
    --source_index;
  }
  Result<Transform> ancestor_from_target = ancestor_from_frame(target_path, target_index, time_ns);
  if (!ancestor_from_target) return ancestor_from_target.error();
  Result<Transform> ancestor_from_source = ancestor_from_frame(source_path, source_index, time_ns);
  if (!ancestor_from_source) return ancestor_from_source.error();
  return Transform(ancestor_from_target.value().inverse() * ancestor_from_source.value());
}

Status FrameTree::set_calibration(const std::string& joint_name, const Transform& parent_from_child,
                                  const CalibrationRecord& record) {
  const auto found = joints_.find(joint_name);
  if (found == joints_.end()) return Error{.message = "no such joint", .file = source_path_, .field = joint_name};
  if (found->second.tracked)
    return Error{
        .message = "a tracked (floating) joint cannot be calibrated", .file = source_path_, .field = joint_name};
  found->second.parent_from_child = parent_from_child;
  found->second.record = record;
  return Done{};
}

Status FrameTree::save(const std::string& path) const {
  tinyxml2::XMLDocument document;
  document.Parse(xml_.c_str(), xml_.size());
  for (auto* element = document.FirstChildElement("robot")->FirstChildElement("joint"); element;
       element = element->NextSiblingElement("joint")) {
    const FrameJoint& joint = joints_.at(element->Attribute("name"));
    if (!joint.record) continue;
    tinyxml2::XMLElement* origin = element->FirstChildElement("origin");
    if (origin == nullptr) origin = element->InsertNewChildElement("origin");
    origin->SetAttribute("xyz", format_triple(joint.parent_from_child.translation()).c_str());
    origin->SetAttribute("rpy", format_triple(rotation_to_rpy(joint.parent_from_child.rotation())).c_str());
    origin->SetAttribute("nav_calibrated", joint.record->date.c_str());
    origin->SetAttribute("nav_residual_m", joint.record->residual_m);
  }
  if (document.SaveFile(path.c_str()) != tinyxml2::XML_SUCCESS)
    return Error{.message = "cannot write the URDF", .file = path};
  return Done{};
}

}  // namespace nav::calibration
