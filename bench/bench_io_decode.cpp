// Decoding throughput of the packet decoders on real captures, in points per second, and the
// ratio to a live HDL-64E (~1.3 M points/s): `x_hdl64e_realtime` > 1 means faster than the
// sensor produces data. The packets are read into memory first so that the Decode benchmarks time
// decoding and sweep assembly only; the FrameSource benchmarks include reading the file.
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "fieldlidar/io/frame_source.hpp"
#include "fieldlidar/io/ouster.hpp"
#include "fieldlidar/io/pcap.hpp"
#include "fieldlidar/io/velodyne.hpp"

namespace fs = std::filesystem;
using namespace fieldlidar;

namespace {

constexpr double kHdl64ePointsPerSecond = 1.3e6;

fs::path data(const std::string& relative) {
  const char* env = std::getenv("FIELDLIDAR_DATA_DIR");
  return fs::path(env && *env ? env : FIELDLIDAR_DEFAULT_DATA_DIR) / relative;
}

std::vector<std::vector<std::uint8_t>> payloads(const fs::path& pcap, std::size_t bytes) {
  std::vector<std::vector<std::uint8_t>> out;
  io::PcapReader reader(pcap);
  while (auto d = reader.next())
    if (d->payload.size() == bytes) out.emplace_back(d->payload.begin(), d->payload.end());
  return out;
}

void report(benchmark::State& state, std::size_t points) {
  state.counters["points"] = double(points);
  state.counters["points_per_s"] =
      benchmark::Counter(double(points), benchmark::Counter::kIsIterationInvariantRate);
  state.counters["x_hdl64e_realtime"] = benchmark::Counter(
      double(points) / kHdl64ePointsPerSecond, benchmark::Counter::kIsIterationInvariantRate);
}

void BM_VelodyneDecode_Hdl32e(benchmark::State& state) {
  const auto path = data("velodyne_pcap/hdl32_example.pcap");
  if (!fs::exists(path)) return state.SkipWithError(("missing " + path.string()).c_str());
  const auto packets = payloads(path, io::kVelodyneDataPacketBytes);
  std::size_t points = 0;
  for (auto _ : state) {
    io::VelodyneSweepAssembler assembler;
    for (std::size_t i = 0; i < packets.size(); ++i)
      assembler.add_packet(packets[i], 1e9 + double(i) * 5.5e-4, "bench");
    assembler.finish();
    points = 0;
    while (auto s = assembler.pop()) points += s->cloud.size();
    benchmark::DoNotOptimize(points);
  }
  report(state, points);
}
BENCHMARK(BM_VelodyneDecode_Hdl32e)->Unit(benchmark::kMillisecond);

void BM_OusterDecode_Os2_128(benchmark::State& state) {
  const auto path = data("ouster_pcap/OS-2-128-U1_v2.3.0_1024x10.pcap");
  const auto meta_path = data("ouster_pcap/OS-2-128-U1_v2.3.0_1024x10.json");
  if (!fs::exists(path) || !fs::exists(meta_path))
    return state.SkipWithError(("missing " + path.string()).c_str());
  const auto meta = io::read_ouster_metadata(meta_path);
  const auto packets = payloads(path, io::ouster_lidar_packet_bytes(meta));
  io::OusterFrameAssembler assembler(meta);
  std::size_t points = 0;
  for (auto _ : state) {
    for (const auto& p : packets) assembler.add_packet(p, "bench");
    assembler.finish();
    points = 0;
    while (auto f = assembler.pop()) points += f->cloud.size();
    benchmark::DoNotOptimize(points);
  }
  report(state, points);
}
BENCHMARK(BM_OusterDecode_Os2_128)->Unit(benchmark::kMillisecond);

/// End to end: FrameSource::open + next() over the whole capture file.
void frame_source(benchmark::State& state, const std::string& rel, const io::SourceOptions& o) {
  const auto path = data(rel);
  if (!fs::exists(path)) return state.SkipWithError(("missing " + path.string()).c_str());
  std::size_t points = 0;
  for (auto _ : state) {
    auto src = io::FrameSource::open(path, o);
    points = 0;
    while (auto f = src->next()) points += f->cloud.size();
    benchmark::DoNotOptimize(points);
  }
  report(state, points);
}
void BM_FrameSource_Hdl32ePcap(benchmark::State& state) {
  frame_source(state, "velodyne_pcap/hdl32_example.pcap", {});
}
BENCHMARK(BM_FrameSource_Hdl32ePcap)->Unit(benchmark::kMillisecond);
void BM_FrameSource_Os2_128Pcap(benchmark::State& state) {
  frame_source(state, "ouster_pcap/OS-2-128-U1_v2.3.0_1024x10.pcap", {});
}
BENCHMARK(BM_FrameSource_Os2_128Pcap)->Unit(benchmark::kMillisecond);
void BM_FrameSource_LegBag(benchmark::State& state) {
  frame_source(state, "legs_2d/negative_2.bag", {.topic = "/left_scan", .metadata = {}});
}
BENCHMARK(BM_FrameSource_LegBag)->Unit(benchmark::kMillisecond);

}  // namespace
