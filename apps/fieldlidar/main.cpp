// fieldlidar: command-line tool for 3D-LiDAR perception, mapping and navigation of field robots.

#include <cstdio>
#include <exception>
#include <string>

#include <CLI/CLI.hpp>

#include "commands.hpp"

namespace {
/// " segment" when a subcommand was named on the command line, "" otherwise.
std::string help_command(const CLI::App& app) {
  for (const auto* sub : app.get_subcommands()) return " " + sub->get_name();
  return "";
}
}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "fieldlidar: 3D-LiDAR perception, mapping and navigation for field robots.\n"
      "Run without a command to see the built-in demo."};
  app.set_version_flag("--version", std::string(FIELDLIDAR_VERSION));
  app.require_subcommand(0, 1);
  fieldlidar::app::add_info_command(app);
  fieldlidar::app::add_segment_command(app);
  fieldlidar::app::add_eval_ground_command(app);
  fieldlidar::app::add_eval_odometry_command(app);
  fieldlidar::app::add_eval_tracking_command(app);
  fieldlidar::app::add_eval_people3d_command(app);
  fieldlidar::app::add_convert_command(app);
  fieldlidar::app::add_demo_command(app);
  fieldlidar::app::add_simulate_command(app);
  fieldlidar::app::add_follow_command(app);
  fieldlidar::app::add_legs_command(app);
  fieldlidar::app::add_legs_train_command(app);
  fieldlidar::app::add_odometry_command(app);
  fieldlidar::app::add_trunks_command(app);
  fieldlidar::app::add_traversability_command(app);
  fieldlidar::app::add_plan_command(app);
  fieldlidar::app::add_navigate_command(app);

  try {
    if (argc == 1)
      app.parse(std::string("demo"), false);  // the built-in default job
    else
      app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    // Every option error as every other error: one line naming the option, exit status 1.
    std::fprintf(stderr, "fieldlidar: error: %s\n", e.what());
    std::fprintf(stderr, "run 'fieldlidar%s --help' for the options and their valid ranges\n",
                 help_command(app).c_str());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fieldlidar: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
