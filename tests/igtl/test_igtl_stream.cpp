// OpenIGTLink over loopback TCP: a sender written with OpenIGTLink's own client socket reaches
// the bridge's listener message by message; a body that fails its CRC is refused and the
// stream goes on; a forged header closes the connection; the listener never takes every
// interface.
#include <gtest/gtest.h>

#include <igtlClientSocket.h>
#include <igtlStringMessage.h>
#include <igtlTransformMessage.h>

#include <thread>
#include <vector>

#include "igtl_test_messages.hpp"
#include "nav/igtl/igtl_stream.hpp"

namespace nav::igtl {
namespace {

constexpr TimeNs kTimeoutNs = 5 * kNsPerSecond;

using nav::testing::packed_bytes;

std::vector<std::uint8_t> transform_message(const char* device, float x_mm) {
  ::igtl::TransformMessage::Pointer message = ::igtl::TransformMessage::New();
  message->SetDeviceName(device);
  ::igtl::Matrix4x4 matrix;
  ::igtl::IdentityMatrix(matrix);
  matrix[0][3] = x_mm;
  message->SetMatrix(matrix);
  return packed_bytes(*message);
}

/// Sends `messages` from an OpenIGTLink client socket to 127.0.0.1:`port`, then closes.
void send_with_openigtlink(int port, const std::vector<std::vector<std::uint8_t>>& messages) {
  ::igtl::ClientSocket::Pointer socket = ::igtl::ClientSocket::New();
  ASSERT_EQ(socket->ConnectToServer("127.0.0.1", port), 0);
  for (const auto& bytes : messages) socket->Send(bytes.data(), static_cast<int>(bytes.size()));
  socket->CloseSocket();
}

TEST(IgtlStream, MessagesFromAnOpenIgtLinkClientArriveOneByOne) {
  auto listener = Listener::listen({"127.0.0.1", 0});
  ASSERT_TRUE(listener.ok()) << listener.error().describe();
  ASSERT_GT(listener.value().port(), 0);
  ::igtl::StringMessage::Pointer text = ::igtl::StringMessage::New();
  text->SetDeviceName("Status");
  text->SetString("hello station");
  const std::vector<std::vector<std::uint8_t>> sent{transform_message("ProbeToTracker", 1.0f),
                                                    transform_message("StylusToTracker", 2.0f), packed_bytes(*text)};
  std::thread sender(send_with_openigtlink, listener.value().port(), sent);
  auto stream = listener.value().accept(kTimeoutNs);
  ASSERT_TRUE(stream.ok()) << stream.error().describe();
  const char* devices[] = {"ProbeToTracker", "StylusToTracker", "Status"};
  for (std::size_t k = 0; k < sent.size(); ++k) {
    const auto message = stream.value().read(kTimeoutNs);
    ASSERT_TRUE(message.ok()) << message.error().describe();
    EXPECT_EQ(message.value().header.device, devices[k]);
    EXPECT_EQ(message.value().body.size() + kHeaderBytes, sent[k].size());
  }
  const auto after = stream.value().read(kTimeoutNs);  // the sender closed
  EXPECT_FALSE(after.ok());
  EXPECT_FALSE(stream.value().open());
  sender.join();
}

TEST(IgtlStream, ABodyFailingItsCrcIsRefusedAndTheNextMessageStillArrives) {
  auto listener = Listener::listen({"127.0.0.1", 0});
  ASSERT_TRUE(listener.ok());
  auto corrupt = transform_message("ProbeToTracker", 1.0f);
  corrupt.back() ^= 0x10;
  std::thread sender(send_with_openigtlink, listener.value().port(),
                     std::vector{corrupt, transform_message("ProbeToTracker", 3.0f)});
  auto stream = listener.value().accept(kTimeoutNs);
  ASSERT_TRUE(stream.ok());
  const auto refused = stream.value().read(kTimeoutNs);
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.error().field, "crc");
  EXPECT_NE(refused.error().file.find("127.0.0.1:"), std::string::npos);  // names the sender
  EXPECT_TRUE(stream.value().open());
  const auto next = stream.value().read(kTimeoutNs);
  ASSERT_TRUE(next.ok()) << next.error().describe();
  sender.join();
}

TEST(IgtlStream, AForgedHeaderClosesTheConnectionWithoutReadingItsBody) {
  auto listener = Listener::listen({"127.0.0.1", 0});
  ASSERT_TRUE(listener.ok());
  auto forged = transform_message("ProbeToTracker", 1.0f);
  for (int i = 42; i < 50; ++i) forged[static_cast<std::size_t>(i)] = 0xff;  // a body of 16 EiB
  std::thread sender(send_with_openigtlink, listener.value().port(), std::vector<std::vector<std::uint8_t>>{forged});
  auto stream = listener.value().accept(kTimeoutNs);
  ASSERT_TRUE(stream.ok());
  const auto refused = stream.value().read(kTimeoutNs);
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.error().field, "body_size");
  EXPECT_FALSE(stream.value().open());
  sender.join();
}

TEST(IgtlStream, WhatOneStreamWritesTheOtherReads) {
  auto listener = Listener::listen({"127.0.0.1", 0});
  ASSERT_TRUE(listener.ok());
  auto client = MessageStream::connect({"127.0.0.1", listener.value().port()}, kTimeoutNs);
  ASSERT_TRUE(client.ok()) << client.error().describe();
  auto server = listener.value().accept(kTimeoutNs);
  ASSERT_TRUE(server.ok());
  const auto bytes = transform_message("NeedleTipToReference", 5.0f);
  ASSERT_TRUE(server.value().write(bytes).ok());
  const auto message = client.value().read(kTimeoutNs);
  ASSERT_TRUE(message.ok()) << message.error().describe();
  EXPECT_EQ(message.value().header.device, "NeedleTipToReference");
}

TEST(IgtlStream, TheListenerTakesOneNamedAddressNeverEveryInterface) {
  const auto every = Listener::listen({"0.0.0.0", 0});
  ASSERT_FALSE(every.ok());
  EXPECT_EQ(every.error().field, "host");
  const auto named = Listener::listen({"localhost", 0});  // a name, not an address
  ASSERT_FALSE(named.ok());
  EXPECT_EQ(named.error().field, "host");
  const auto nobody = MessageStream::connect({"127.0.0.1", 1}, kTimeoutNs);  // nothing listens on port 1
  EXPECT_FALSE(nobody.ok());
}

}  // namespace
}  // namespace nav::igtl
