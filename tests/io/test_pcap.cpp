// PcapReader on hand-made captures: UDP payloads, IPv4 fragments, wrong-size sensor packets.
#include <cstring>
#include <fstream>

#include <gtest/gtest.h>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/io/frame_source.hpp"
#include "fieldlidar/io/pcap.hpp"
#include "test_data.hpp"

namespace fieldlidar {
namespace {

/// Writes a classic little-endian Ethernet pcap; each record is one IPv4 packet whose payload
/// (UDP header included when `fragment_offset` is 0) is given.
class PcapWriter {
 public:
  explicit PcapWriter(const std::filesystem::path& p) : out_(p, std::ios::binary) {
    const std::uint32_t magic = 0xa1b2c3d4, snap = 262144, link = 1;
    const std::uint16_t major = 2, minor = 4;
    const std::int32_t zone = 0;
    const std::uint32_t sig = 0;
    put(magic), put(major), put(minor), put(zone), put(sig), put(snap), put(link);
  }
  void udp(std::uint16_t port, const std::vector<std::uint8_t>& payload) {
    std::vector<std::uint8_t> u(8);
    be16(u, 0, port), be16(u, 2, port), be16(u, 4, std::uint16_t(payload.size() + 8));
    u.insert(u.end(), payload.begin(), payload.end());
    ip(u, 0, false, 1);
  }
  /// A UDP datagram in two IPv4 fragments (split at `split` bytes of the UDP datagram, a
  /// multiple of 8).
  void fragmented_udp(std::uint16_t port, const std::vector<std::uint8_t>& payload,
                      std::size_t split) {
    std::vector<std::uint8_t> u(8);
    be16(u, 0, port), be16(u, 2, port), be16(u, 4, std::uint16_t(payload.size() + 8));
    u.insert(u.end(), payload.begin(), payload.end());
    ip({u.begin(), u.begin() + std::ptrdiff_t(split)}, 0, true, 9);
    ip({u.begin() + std::ptrdiff_t(split), u.end()}, split, false, 9);
  }

 private:
  template <class T>
  void put(T v) {
    out_.write(reinterpret_cast<const char*>(&v), sizeof v);
  }
  static void be16(std::vector<std::uint8_t>& b, std::size_t at, std::uint16_t v) {
    b[at] = std::uint8_t(v >> 8), b[at + 1] = std::uint8_t(v);
  }
  void ip(const std::vector<std::uint8_t>& body, std::size_t offset, bool more, std::uint16_t id) {
    std::vector<std::uint8_t> f(14 + 20, 0);
    f[12] = 0x08;  // IPv4 ethertype
    f[14] = 0x45;
    be16(f, 16, std::uint16_t(20 + body.size()));
    be16(f, 18, id);
    be16(f, 20, std::uint16_t((more ? 0x2000 : 0) | (offset / 8)));
    f[22] = 64, f[23] = 17;
    f.insert(f.end(), body.begin(), body.end());
    const std::uint32_t sec = 1000, usec = 0, len = std::uint32_t(f.size());
    put(sec), put(usec), put(len), put(len);
    out_.write(reinterpret_cast<const char*>(f.data()), std::streamsize(f.size()));
  }
  std::ofstream out_;
};

TEST(Pcap, ReadsUdpPayloadsAndReassemblesFragments) {
  const auto dir = test::temp_dir("pcap_reader");
  std::vector<std::uint8_t> big(3000);
  for (std::size_t i = 0; i < big.size(); ++i) big[i] = std::uint8_t(i * 7);
  {
    PcapWriter w(dir / "a.pcap");
    w.udp(1234, {1, 2, 3});
    w.fragmented_udp(7502, big, 1480);
  }
  io::PcapReader r(dir / "a.pcap");
  auto d = r.next();
  ASSERT_TRUE(d);
  EXPECT_EQ(d->dst_port, 1234);
  EXPECT_EQ(d->payload.size(), 3u);
  d = r.next();
  ASSERT_TRUE(d);
  EXPECT_EQ(d->dst_port, 7502);
  ASSERT_EQ(d->payload.size(), big.size());
  EXPECT_EQ(std::memcmp(d->payload.data(), big.data(), big.size()), 0);
  EXPECT_FALSE(r.next());
  EXPECT_DOUBLE_EQ(r.progress(), 1.0);
}

TEST(Pcap, WrongSizeVelodynePacketIsReported) {
  const auto dir = test::temp_dir("pcap_wrong_size");
  std::vector<std::uint8_t> good(1206, 0);
  for (int b = 0; b < 12; ++b)
    good[std::size_t(b * 100)] = 0xFF, good[std::size_t(b * 100 + 1)] = 0xEE;
  good[1204] = 0x37, good[1205] = 0x22;
  {
    PcapWriter w(dir / "v.pcap");
    w.udp(2368, good);
    w.udp(2368, std::vector<std::uint8_t>(1000, 0));
  }
  auto src = io::FrameSource::open(dir / "v.pcap");
  EXPECT_EQ(src->format(), "velodyne-pcap");
  try {
    while (src->next()) {
    }
    FAIL() << "a 1000-byte packet on the data port must be reported";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("1000-byte"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("record 1"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace fieldlidar
