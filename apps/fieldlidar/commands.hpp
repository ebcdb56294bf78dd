#pragma once
// Subcommands of the fieldlidar tool. Each add_*_command registers one subcommand whose callback
// does the work and throws (fieldlidar::Error or std::exception) on failure; main() reports it.

#include <CLI/CLI.hpp>

namespace fieldlidar::app {

void add_info_command(CLI::App& app);
void add_segment_command(CLI::App& app);
void add_eval_ground_command(CLI::App& app);
void add_eval_odometry_command(CLI::App& app);
void add_eval_tracking_command(CLI::App& app);
void add_eval_people3d_command(CLI::App& app);
void add_convert_command(CLI::App& app);
void add_demo_command(CLI::App& app);
void add_simulate_command(CLI::App& app);
void add_follow_command(CLI::App& app);
void add_legs_command(CLI::App& app);
void add_legs_train_command(CLI::App& app);
void add_odometry_command(CLI::App& app);
void add_trunks_command(CLI::App& app);
void add_traversability_command(CLI::App& app);
void add_plan_command(CLI::App& app);
void add_navigate_command(CLI::App& app);

}  // namespace fieldlidar::app
