#include "fieldlidar/io/pcap.hpp"

#include <pcap/pcap.h>

#include <cstdio>
#include <string>

#include "fieldlidar/core/error.hpp"

namespace fieldlidar::io {
namespace {

std::uint16_t be16(const std::uint8_t* p) {
  return std::uint16_t((p[0] << 8) | p[1]);
}

constexpr int kLinkNull = 0;      // BSD loopback: 4-byte address family
constexpr int kLinkEthernet = 1;  // DLT_EN10MB
constexpr int kLinkRaw = 101;     // DLT_RAW (IP first), also 12 and 14 on some systems
constexpr int kLinkSll = 113;     // Linux cooked capture
constexpr int kLinkSll2 = 276;    // Linux cooked capture v2

}  // namespace

struct PcapReader::Impl {
  pcap_t* handle = nullptr;
  int linktype = 0;
  std::size_t record = 0;
  std::uintmax_t file_bytes = 0;
  // IPv4 reassembly of one datagram at a time (fragments in order).
  std::vector<std::uint8_t> frag;
  std::uint16_t frag_id = 0;
  std::size_t frag_next_offset = 0;
  bool frag_active = false;
  std::vector<std::uint8_t> datagram;
};

PcapReader::PcapReader(const std::filesystem::path& path)
    : impl_(std::make_unique<Impl>()), path_(path) {
  if (!std::filesystem::exists(path)) throw Error(path.string() + ": no such file");
  char err[PCAP_ERRBUF_SIZE] = {};
  impl_->handle = pcap_open_offline(path.c_str(), err);
  if (!impl_->handle) throw Error(path.string() + ": not a readable packet capture (" + err + ")");
  impl_->linktype = pcap_datalink(impl_->handle);
  std::error_code ec;
  impl_->file_bytes = std::filesystem::file_size(path, ec);
  const int lt = impl_->linktype;
  if (lt != kLinkNull && lt != kLinkEthernet && lt != kLinkRaw && lt != 12 && lt != 14 &&
      lt != kLinkSll && lt != kLinkSll2) {
    pcap_close(impl_->handle);
    impl_->handle = nullptr;
    throw Error(path.string() + ": unsupported capture link type " + std::to_string(lt) +
                " (expected Ethernet, Linux cooked, raw IP or loopback)");
  }
}

PcapReader::~PcapReader() {
  if (impl_ && impl_->handle) pcap_close(impl_->handle);
}

double PcapReader::progress() const {
  if (!impl_->handle || impl_->file_bytes == 0) return 1.0;
  FILE* f = pcap_file(impl_->handle);
  if (!f) return 0.0;
  const long pos = std::ftell(f);
  return pos < 0 ? 0.0 : std::min(1.0, double(pos) / double(impl_->file_bytes));
}

std::optional<UdpDatagram> PcapReader::next() {
  Impl& s = *impl_;
  for (;;) {
    pcap_pkthdr* hdr = nullptr;
    const u_char* data = nullptr;
    if (truncated_) return std::nullopt;
    const int rc = pcap_next_ex(s.handle, &hdr, &data);
    if (rc == PCAP_ERROR_BREAK) return std::nullopt;
    if (rc != 1) {
      const std::string why = pcap_geterr(s.handle);
      // libpcap: "truncated dump file; tried to read N captured bytes, only got M" (also for
      // record headers and pcapng blocks): the end of a capture whose recorder was killed.
      if (rc == PCAP_ERROR && why.find("truncated") != std::string::npos) {
        truncated_ = path_.string() + ": the capture ends inside record " +
                     std::to_string(s.record) + " (" + why +
                     "): read up to the cut, the rest is lost (was the recorder killed?)";
        return std::nullopt;
      }
      throw Error(path_.string() + ": capture record " + std::to_string(s.record) +
                  " cannot be read: " + why);
    }
    const std::size_t rec = s.record++;
    const double stamp_s = double(hdr->ts.tv_sec) + 1e-6 * double(hdr->ts.tv_usec);
    const std::uint8_t* p = data;
    std::size_t n = hdr->caplen;
    // Link layer -> network protocol.
    int proto = 0;  // 4 or 6
    auto ethertype_proto = [](std::uint16_t et) { return et == 0x0800 ? 4 : et == 0x86DD ? 6 : 0; };
    if (s.linktype == kLinkEthernet) {
      if (n < 14) continue;
      std::uint16_t et = be16(p + 12);
      std::size_t off = 14;
      while ((et == 0x8100 || et == 0x88A8) && n >= off + 4) {
        et = be16(p + off + 2);
        off += 4;
      }
      proto = ethertype_proto(et);
      p += off;
      n -= off;
    } else if (s.linktype == kLinkSll) {
      if (n < 16) continue;
      proto = ethertype_proto(be16(p + 14));
      p += 16;
      n -= 16;
    } else if (s.linktype == kLinkSll2) {
      if (n < 20) continue;
      proto = ethertype_proto(be16(p));
      p += 20;
      n -= 20;
    } else if (s.linktype == kLinkNull) {
      if (n < 4) continue;
      const std::uint32_t fam = std::uint32_t(p[0]) | std::uint32_t(p[1]) << 8;
      proto = fam == 2 ? 4 : (fam == 24 || fam == 28 || fam == 30) ? 6 : 0;
      p += 4;
      n -= 4;
    } else {
      if (n < 1) continue;
      proto = (p[0] >> 4) == 4 ? 4 : (p[0] >> 4) == 6 ? 6 : 0;
    }
    const std::uint8_t* udp = nullptr;
    std::size_t udp_avail = 0;
    if (proto == 4) {
      if (n < 20 || (p[0] >> 4) != 4) continue;
      const std::size_t ihl = std::size_t(p[0] & 0x0F) * 4;
      const std::size_t total = be16(p + 2);
      if (ihl < 20 || n < ihl || p[9] != 17) continue;
      const std::size_t ip_payload = total >= ihl ? std::min(total, n) - ihl : 0;
      const std::uint16_t flags = be16(p + 6);
      const bool more = flags & 0x2000;
      const std::size_t frag_off = std::size_t(flags & 0x1FFF) * 8;
      if (more || frag_off != 0) {
        const std::uint16_t id = be16(p + 4);
        if (frag_off == 0) {
          s.frag.assign(p + ihl, p + ihl + ip_payload);
          s.frag_id = id;
          s.frag_next_offset = ip_payload;
          s.frag_active = true;
        } else if (s.frag_active && id == s.frag_id && frag_off == s.frag_next_offset) {
          s.frag.insert(s.frag.end(), p + ihl, p + ihl + ip_payload);
          s.frag_next_offset += ip_payload;
        } else {
          s.frag_active = false;  // out of order or lost: drop the datagram
          continue;
        }
        if (more) continue;
        s.frag_active = false;
        s.datagram.swap(s.frag);
        udp = s.datagram.data();
        udp_avail = s.datagram.size();
      } else {
        udp = p + ihl;
        udp_avail = ip_payload;
      }
    } else if (proto == 6) {
      if (n < 40 || p[6] != 17) continue;  // no extension headers
      udp = p + 40;
      udp_avail = std::min<std::size_t>(be16(p + 4), n - 40);
    } else {
      continue;
    }
    if (udp_avail < 8) continue;
    const std::size_t udp_len = be16(udp + 4);
    if (udp_len < 8) continue;
    if (udp_len > udp_avail)
      throw Error(path_.string() + ": capture record " + std::to_string(rec) + " holds " +
                  std::to_string(udp_avail - 8) + " of the " + std::to_string(udp_len - 8) +
                  " bytes of its UDP datagram (cut by the capture's snap length or truncated)");
    UdpDatagram d;
    d.stamp_s = stamp_s;
    d.record = rec;
    d.src_port = be16(udp);
    d.dst_port = be16(udp + 2);
    d.payload = std::span<const std::uint8_t>(udp + 8, udp_len - 8);
    return d;
  }
}

}  // namespace fieldlidar::io
