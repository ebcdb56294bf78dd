// Names of the Velodyne models and return modes, and the SensorModel preset of each model.
#include "fieldlidar/io/velodyne.hpp"

namespace fieldlidar::io {

std::string to_string(VelodyneModel model) {
  switch (model) {
    case VelodyneModel::kVlp16:
      return "VLP-16";
    case VelodyneModel::kVlp32c:
      return "VLP-32C";
    case VelodyneModel::kHdl32e:
      return "HDL-32E";
    case VelodyneModel::kHdl64e:
      return "HDL-64E";
  }
  return "unknown";
}

std::string to_string(VelodyneReturnMode mode) {
  switch (mode) {
    case VelodyneReturnMode::kStrongest:
      return "strongest";
    case VelodyneReturnMode::kLast:
      return "last";
    case VelodyneReturnMode::kDual:
      return "dual";
    case VelodyneReturnMode::kUnknown:
      return "unknown";
  }
  return "unknown";
}

SensorModel sensor_model_of(VelodyneModel model) {
  switch (model) {
    case VelodyneModel::kVlp16:
      return SensorModel::vlp16();
    case VelodyneModel::kVlp32c:
      return SensorModel::vlp32c();
    case VelodyneModel::kHdl32e:
      return SensorModel::hdl32e();
    case VelodyneModel::kHdl64e:
      return SensorModel::hdl64e();
  }
  return SensorModel::vlp16();
}

}  // namespace fieldlidar::io
