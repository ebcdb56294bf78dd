#pragma once
/// \file Reading UDP datagrams out of a packet capture (.pcap from tcpdump, Wireshark, VeloView).

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace fieldlidar::io {

/// One UDP datagram of a capture. `payload` stays valid until the next call to PcapReader::next().
struct UdpDatagram {
  double stamp_s = 0;      ///< capture time, s since the Unix epoch
  std::size_t record = 0;  ///< 0-based index of the capture record that completed it
  std::uint16_t src_port = 0;
  std::uint16_t dst_port = 0;
  std::span<const std::uint8_t> payload;
};

/// Streams the UDP datagrams of a capture one at a time (nothing is loaded whole). Handles
/// Ethernet (with VLAN tags), Linux cooked (SLL, SLL2), raw-IP and BSD loopback link layers, IPv4
/// and IPv6, and reassembles IPv4 fragments that arrive in order (sensors sending datagrams larger
/// than the MTU, e.g. Ouster, are captured as fragments). Non-UDP records are skipped.
class PcapReader {
 public:
  /// Throws fieldlidar::Error naming the file when it is missing or not a capture.
  explicit PcapReader(const std::filesystem::path& path);
  ~PcapReader();
  PcapReader(const PcapReader&) = delete;
  PcapReader& operator=(const PcapReader&) = delete;

  /// Next UDP datagram, nullopt at the end. A capture that ends inside a record (the recorder was
  /// killed) ends there: nullopt, and truncated() says so. Throws fieldlidar::Error for other read
  /// errors and for a datagram cut short by the capture's snap length.
  std::optional<UdpDatagram> next();
  /// Set once next() has met the end of the file inside a record: which record, what is missing.
  const std::optional<std::string>& truncated() const { return truncated_; }
  /// Fraction of the file read so far, in [0, 1].
  double progress() const;
  const std::filesystem::path& path() const { return path_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::filesystem::path path_;
  std::optional<std::string> truncated_;
};

}  // namespace fieldlidar::io
