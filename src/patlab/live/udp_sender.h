// Sending packets by UDP (POSIX sockets, IPv4): to one host (unicast) or to a multicast group,
// as SSL-Vision does (224.5.23.2:10006). For a multicast group the socket gets the packets' TTL
// (IP_MULTICAST_TTL: 1 keeps them on the local network), the interface they leave by
// (IP_MULTICAST_IF, when one is named) and whether this host's own sockets receive them
// (IP_MULTICAST_LOOP); constructing a sender sets these up and sends nothing.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>

namespace patlab::live {

struct UdpAddress {
  std::string host;        // the dotted IPv4 address as given
  uint32_t ipv4 = 0;       // host byte order
  uint16_t port = 0;       // 1..65535
  bool multicast = false;  // 224.0.0.0/4
};

// "A.B.C.D:PORT" -> UdpAddress. InputError naming `flag`: "<flag> is '<text>'; expected
// ADDRESS:PORT with a dotted IPv4 address and a port in 1..65535, e.g. 224.5.23.2:10006".
UdpAddress ParseUdpAddress(std::string_view text, std::string_view flag);

struct UdpSenderOptions {
  // Hops a multicast packet may take (IP_MULTICAST_TTL), in [0, 255]: 1 = this network only.
  int ttl = 1;
  // The interface multicast packets leave by (IP_MULTICAST_IF): its IPv4 address or its name
  // (e.g. "eth0", resolved to its first IPv4 address); empty: the system's choice (the route).
  std::string iface;
  // Whether processes on this host receive the multicast packets too (IP_MULTICAST_LOOP): on,
  // so that an AI on the same machine sees them.
  bool loop = true;
};

class UdpSender {
 public:
  // Opens the socket and sets it up. InputError for a bad ttl or an unknown interface (naming
  // --ttl / --iface); EnvironmentError when the system refuses the socket.
  UdpSender(const UdpAddress& address, const UdpSenderOptions& options);
  virtual ~UdpSender();
  UdpSender(const UdpSender&) = delete;
  UdpSender& operator=(const UdpSender&) = delete;

  // Sends one datagram. Returns false (and counts it, last_error() says why) when the system did
  // not take it (no route, buffer full); the live loop tries it again, then goes on with the next
  // packet rather than stopping. Virtual so that a test's sender can fail on purpose.
  virtual bool Send(std::span<const uint8_t> bytes);
  bool Send(std::string_view bytes) {
    return Send(
        std::span<const uint8_t>(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size()));
  }

  int socket_fd() const { return fd_; }  // for tests that read the options back
  const UdpAddress& address() const { return address_; }
  long sent() const { return sent_; }
  long failed() const { return failed_; }
  // Why the last failed Send failed (the system's error text); empty before any failure.
  const std::string& last_error() const { return last_error_; }

 protected:
  void SetLastError(std::string text) { last_error_ = std::move(text); }

 private:
  int fd_ = -1;
  UdpAddress address_;
  long sent_ = 0;
  long failed_ = 0;
  std::string last_error_;
};

// The IPv4 address (host byte order) of an interface named by address or name; InputError
// naming --iface when there is none.
uint32_t InterfaceAddress(const std::string& iface);

}  // namespace patlab::live
