// The largest uncompressed chunk of a ROS1 bag, read from its own index: rosbag_storage copies a
// message by the length its record claims, out of the chunk buffer, without checking it against
// the chunk, so a damaged record would read far past it.
#include <array>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "rosbag_common.hpp"

namespace fieldlidar::io::rosbag_detail {
namespace {

/// One record's header fields (name=value pairs), read at the stream's position; the stream is
/// left after the header, at the record's data length. False on a short or absurd header.
bool read_header(std::ifstream& in, std::uint64_t file_size,
                 std::vector<std::pair<std::string, std::string>>& fields) {
  fields.clear();
  std::uint32_t header_len = 0;
  if (!in.read(reinterpret_cast<char*>(&header_len), 4)) return false;
  const auto at = std::uint64_t(in.tellg());
  if (header_len > file_size - at) return false;
  std::string header(header_len, '\0');
  if (!in.read(header.data(), header_len)) return false;
  for (std::size_t i = 0; i + 4 <= header.size();) {
    std::uint32_t n = 0;
    std::memcpy(&n, header.data() + i, 4);
    i += 4;
    if (n > header.size() - i) return false;
    const std::string field = header.substr(i, n);
    i += n;
    const auto eq = field.find('=');
    if (eq == std::string::npos) return false;
    fields.emplace_back(field.substr(0, eq), field.substr(eq + 1));
  }
  return true;
}

template <class T>
bool field_of(const std::vector<std::pair<std::string, std::string>>& fields, const char* name,
              T& value) {
  for (const auto& [k, v] : fields)
    if (k == name && v.size() == sizeof(T)) {
      std::memcpy(&value, v.data(), sizeof(T));
      return true;
    }
  return false;
}

constexpr std::uint8_t kOpBagHeader = 0x03, kOpChunk = 0x05, kOpChunkInfo = 0x06;

}  // namespace

std::uint64_t bag_max_chunk_bytes(const std::filesystem::path& path) {
  std::error_code ec;
  const std::uint64_t file_size = std::filesystem::file_size(path, ec);
  if (ec) return 0;
  std::ifstream in(path, std::ios::binary);
  std::array<char, 13> magic{};
  if (!in.read(magic.data(), magic.size()) ||
      std::string(magic.data(), magic.size()) != "#ROSBAG V2.0\n")
    return file_size;  // version 1.2 reads each record from the file by its own length
  std::vector<std::pair<std::string, std::string>> fields;
  std::uint8_t op = 0;
  std::uint64_t index_pos = 0;
  if (!read_header(in, file_size, fields) || !field_of(fields, "op", op) || op != kOpBagHeader ||
      !field_of(fields, "index_pos", index_pos) || index_pos >= file_size)
    return 0;
  // The chunk info records after index_pos give every chunk's position.
  std::vector<std::uint64_t> chunks;
  in.seekg(std::streamoff(index_pos));
  while (in && std::uint64_t(in.tellg()) < file_size) {
    if (!read_header(in, file_size, fields)) return 0;
    std::uint32_t data_len = 0;
    if (!in.read(reinterpret_cast<char*>(&data_len), 4)) return 0;
    std::uint64_t chunk_pos = 0;
    if (field_of(fields, "op", op) && op == kOpChunkInfo &&
        field_of(fields, "chunk_pos", chunk_pos))
      chunks.push_back(chunk_pos);
    in.seekg(data_len, std::ios::cur);
  }
  // Each chunk record's header holds its uncompressed size.
  std::uint64_t largest = 0;
  for (const std::uint64_t pos : chunks) {
    if (pos >= file_size) return 0;
    in.clear();
    in.seekg(std::streamoff(pos));
    std::uint32_t size = 0;
    if (!read_header(in, file_size, fields) || !field_of(fields, "op", op) || op != kOpChunk ||
        !field_of(fields, "size", size))
      return 0;
    largest = std::max<std::uint64_t>(largest, size);
  }
  return largest;
}

}  // namespace fieldlidar::io::rosbag_detail
