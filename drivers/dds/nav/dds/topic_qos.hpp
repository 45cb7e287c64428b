#pragma once
// Internal (includes Fast DDS): the QoS of each topic, written in code next to the topic
// list. Poses: best-effort, keep-last 1, with a deadline. Frames: best-effort, keep-last 2,
// data-sharing between processes of one host. Needle, predictions and surfaces: reliable,
// keep-last 1. Health: reliable, transient-local, keep-last 1. Readers and writers agree.
#include <fastdds/dds/publisher/qos/DataWriterQos.hpp>
#include <fastdds/dds/subscriber/qos/DataReaderQos.hpp>

#include "nav/dds/topics.hpp"

namespace nav::dds {

eprosima::fastdds::dds::DataWriterQos writer_qos(Topic topic, const TopicQosOptions& options);
eprosima::fastdds::dds::DataReaderQos reader_qos(Topic topic, const TopicQosOptions& options);

}  // namespace nav::dds
