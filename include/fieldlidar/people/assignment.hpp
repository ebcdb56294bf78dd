#pragma once
/// \file Minimum-cost assignment (Hungarian method) for data association.

#include <cstddef>
#include <vector>

#include <Eigen/Core>

namespace fieldlidar::people {

/// Solves the rectangular assignment problem on `cost` (rows x cols, any sizes): returns for each
/// row the assigned column or -1, minimising the total cost over a maximum matching. Entries that
/// are +infinity (or >= `forbidden`) are never assigned: a row whose only options are forbidden
/// stays unassigned.
std::vector<int> solve_assignment(const Eigen::MatrixXd& cost, double forbidden = 1e17);

}  // namespace fieldlidar::people
