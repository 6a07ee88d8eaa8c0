// UDP sending (udp_sender.h) with POSIX sockets.
#include "patlab/live/udp_sender.h"

#include <arpa/inet.h>
#include <ifaddrs.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <cstring>

#include "patlab/core/error.h"

namespace patlab::live {

namespace {

bool ParseIpv4(std::string_view text, uint32_t* out) {
  const std::string copy(text);
  in_addr addr{};
  if (inet_pton(AF_INET, copy.c_str(), &addr) != 1) return false;
  *out = ntohl(addr.s_addr);
  return true;
}

[[noreturn]] void SocketFailure(const std::string& what) {
  throw EnvironmentError("UDP socket: " + what + ": " + std::strerror(errno));
}

void SetOption(int fd, int option, const void* value, socklen_t size, const char* name) {
  if (setsockopt(fd, IPPROTO_IP, option, value, size) != 0) {
    SocketFailure(std::string("cannot set ") + name);
  }
}

void SetUpMulticast(int fd, const UdpSenderOptions& options) {
  const unsigned char ttl = static_cast<unsigned char>(options.ttl);
  SetOption(fd, IP_MULTICAST_TTL, &ttl, sizeof ttl, "IP_MULTICAST_TTL");
  const unsigned char loop = options.loop ? 1 : 0;
  SetOption(fd, IP_MULTICAST_LOOP, &loop, sizeof loop, "IP_MULTICAST_LOOP");
  if (!options.iface.empty()) {
    in_addr addr{};
    addr.s_addr = htonl(InterfaceAddress(options.iface));
    SetOption(fd, IP_MULTICAST_IF, &addr, sizeof addr, "IP_MULTICAST_IF");
  }
}

}  // namespace

UdpAddress ParseUdpAddress(std::string_view text, std::string_view flag) {
  UdpAddress out;
  const size_t colon = text.rfind(':');
  bool ok = colon != std::string_view::npos && ParseIpv4(text.substr(0, colon), &out.ipv4);
  if (ok) {
    const std::string_view port = text.substr(colon + 1);
    unsigned value = 0;
    const auto [end, ec] = std::from_chars(port.data(), port.data() + port.size(), value);
    ok = ec == std::errc() && end == port.data() + port.size() && value >= 1 && value <= 65535;
    out.port = static_cast<uint16_t>(value);
  }
  if (!ok) {
    throw InputError(std::string(flag) + " is '" + std::string(text) +
                     "'; expected ADDRESS:PORT with a dotted IPv4 address and a port in "
                     "1..65535, e.g. 127.0.0.1:10006");
  }
  out.host = std::string(text.substr(0, colon));
  out.multicast = (out.ipv4 >> 28) == 0xE;
  return out;
}

uint32_t InterfaceAddress(const std::string& iface) {
  uint32_t address = 0;
  if (ParseIpv4(iface, &address)) return address;
  ifaddrs* list = nullptr;
  if (getifaddrs(&list) != 0) SocketFailure("cannot list the interfaces");
  bool found = false;
  for (ifaddrs* i = list; i != nullptr && !found; i = i->ifa_next) {
    if (i->ifa_addr == nullptr || i->ifa_addr->sa_family != AF_INET || iface != i->ifa_name) {
      continue;
    }
    address = ntohl(reinterpret_cast<const sockaddr_in*>(i->ifa_addr)->sin_addr.s_addr);
    found = true;
  }
  freeifaddrs(list);
  if (!found) {
    throw InputError("--iface is '" + iface +
                     "'; expected an IPv4 address or the name of an interface with one");
  }
  return address;
}

UdpSender::UdpSender(const UdpAddress& address, const UdpSenderOptions& options)
    : address_(address) {
  if (options.ttl < 0 || options.ttl > 255) {
    throw InputError("--ttl is " + std::to_string(options.ttl) + "; expected 0..255");
  }
  if (address.multicast && !options.iface.empty()) InterfaceAddress(options.iface);
  fd_ = socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  if (fd_ < 0) SocketFailure("cannot open");
  try {
    if (address.multicast) SetUpMulticast(fd_, options);
  } catch (...) {
    close(fd_);
    throw;
  }
}

UdpSender::~UdpSender() {
  if (fd_ >= 0) close(fd_);
}

bool UdpSender::Send(std::span<const uint8_t> bytes) {
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_port = htons(address_.port);
  to.sin_addr.s_addr = htonl(address_.ipv4);
  const ssize_t n = sendto(fd_, bytes.data(), bytes.size(), MSG_NOSIGNAL,
                           reinterpret_cast<const sockaddr*>(&to), sizeof to);
  const bool ok = n == static_cast<ssize_t>(bytes.size());
  ++(ok ? sent_ : failed_);
  if (!ok) last_error_ = n < 0 ? std::strerror(errno) : "the datagram was cut short";
  return ok;
}

}  // namespace patlab::live
