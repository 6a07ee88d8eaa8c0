// The UDP sender (live/udp_sender.h): addresses parsed, the multicast socket's options read back
// from the socket (nothing is sent to a group), and datagrams sent to 127.0.0.1 on an ephemeral
// port received by a socket of the test.
#include "patlab/live/udp_sender.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include "../expect_error.h"

namespace patlab::live {
namespace {

TEST(UdpAddress, ParsesUnicastAndMulticast) {
  const UdpAddress a = ParseUdpAddress("127.0.0.1:10006", "--send");
  EXPECT_EQ(a.host, "127.0.0.1");
  EXPECT_EQ(a.ipv4, 0x7f000001u);
  EXPECT_EQ(a.port, 10006);
  EXPECT_FALSE(a.multicast);
  const UdpAddress m = ParseUdpAddress("224.5.23.2:10006", "--send");
  EXPECT_EQ(m.ipv4, 0xe0051702u);
  EXPECT_TRUE(m.multicast);
  EXPECT_TRUE(ParseUdpAddress("239.255.255.255:1", "--send").multicast);
  EXPECT_FALSE(ParseUdpAddress("223.255.255.255:1", "--send").multicast);
}

TEST(UdpAddress, RejectsMalformedAddresses) {
  const std::string expected =
      "'; expected ADDRESS:PORT with a dotted IPv4 address and a port in 1..65535, e.g. "
      "127.0.0.1:10006";
  for (const char* bad : {"127.0.0.1", "127.0.0.1:", "127.0.0.1:0", "127.0.0.1:65536",
                          "localhost:10006", "1.2.3:5", "127.0.0.1:10x", ":10006"}) {
    EXPECT_INPUT_ERROR(ParseUdpAddress(bad, "--send"), std::string("--send is '") + bad + expected);
  }
}

// The option values the socket holds, read with getsockopt.
int ByteOption(int fd, int option) {
  unsigned char value = 0;
  socklen_t size = sizeof value;
  EXPECT_EQ(getsockopt(fd, IPPROTO_IP, option, &value, &size), 0);
  return value;
}

TEST(UdpSender, MulticastSocketIsSetUpAndSendsNothing) {
  const UdpAddress group = ParseUdpAddress("224.5.23.2:10006", "--send");
  UdpSender sender(group, UdpSenderOptions{3, "127.0.0.1", false});
  EXPECT_EQ(ByteOption(sender.socket_fd(), IP_MULTICAST_TTL), 3);
  EXPECT_EQ(ByteOption(sender.socket_fd(), IP_MULTICAST_LOOP), 0);
  in_addr iface{};
  socklen_t size = sizeof iface;
  ASSERT_EQ(getsockopt(sender.socket_fd(), IPPROTO_IP, IP_MULTICAST_IF, &iface, &size), 0);
  EXPECT_EQ(ntohl(iface.s_addr), 0x7f000001u);
  EXPECT_EQ(sender.sent(), 0);
}

TEST(UdpSender, MulticastDefaultsAndInterfaceByName) {
  const UdpAddress group = ParseUdpAddress("224.5.23.2:10006", "--send");
  UdpSender sender(group, UdpSenderOptions{1, "lo", true});
  EXPECT_EQ(ByteOption(sender.socket_fd(), IP_MULTICAST_TTL), 1);
  EXPECT_EQ(ByteOption(sender.socket_fd(), IP_MULTICAST_LOOP), 1);
  in_addr iface{};
  socklen_t size = sizeof iface;
  ASSERT_EQ(getsockopt(sender.socket_fd(), IPPROTO_IP, IP_MULTICAST_IF, &iface, &size), 0);
  EXPECT_EQ(ntohl(iface.s_addr), 0x7f000001u);
}

TEST(UdpSender, RejectsBadTtlAndInterface) {
  const UdpAddress group = ParseUdpAddress("224.5.23.2:10006", "--send");
  EXPECT_INPUT_ERROR(UdpSender(group, UdpSenderOptions{256, "", true}),
                     "--ttl is 256; expected 0..255");
  EXPECT_INPUT_ERROR(UdpSender(group, UdpSenderOptions{1, "no-such-interface", true}),
                     "--iface is 'no-such-interface'; expected an IPv4 address or the name of an "
                     "interface with one");
}

// A socket of the test bound to 127.0.0.1 on a port the system picks.
struct Receiver {
  int fd = socket(AF_INET, SOCK_DGRAM, 0);
  uint16_t port = 0;
  Receiver() {
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    EXPECT_EQ(bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr), 0);
    socklen_t size = sizeof addr;
    EXPECT_EQ(getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &size), 0);
    port = ntohs(addr.sin_port);
  }
  ~Receiver() { close(fd); }
  // The next datagram, or "" after 5 s without one.
  std::string Receive() const {
    pollfd p{fd, POLLIN, 0};
    if (poll(&p, 1, 5000) != 1) return "";
    char buffer[65536];
    const ssize_t n = recv(fd, buffer, sizeof buffer, 0);
    return n > 0 ? std::string(buffer, static_cast<size_t>(n)) : "";
  }
};

TEST(UdpSender, LoopbackDatagramsArriveWhole) {
  Receiver receiver;
  UdpSender sender(ParseUdpAddress("127.0.0.1:" + std::to_string(receiver.port), "--send"), {});
  const std::string first = "first packet";
  std::string second(1400, '\0');
  for (size_t i = 0; i < second.size(); ++i) second[i] = static_cast<char>(i * 7);
  EXPECT_TRUE(sender.Send(first));
  EXPECT_TRUE(sender.Send(second));
  EXPECT_EQ(receiver.Receive(), first);
  EXPECT_EQ(receiver.Receive(), second);
  EXPECT_EQ(sender.sent(), 2);
  EXPECT_EQ(sender.failed(), 0);
}

}  // namespace
}  // namespace patlab::live
