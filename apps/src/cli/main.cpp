// SPDX-License-Identifier: Apache-2.0
#include <morph/exceptions.h>

#include <iostream>

#if defined(__GLIBC__)
#include <malloc.h>
#endif
#if defined(MORPHMILL_TBBMALLOC_PROXY)
#include <oneapi/tbb/tbbmalloc_proxy.h>  // references the proxy, so the linker keeps it
#endif

#include "cli/cli_conventions.h"
#include "cli/commands.h"
#include "io/provenance.h"

int main(int argc, char** argv) {
#if defined(__GLIBC__) && !defined(MORPHMILL_TBBMALLOC_PROXY)
  // With glibc's malloc (TBB's proxy keeps its own pools): the generator's assembly allocates and frees
  // arrays of tens of megabytes over and over (edge lists, triangle copies): glibc would map each one afresh
  // and fault in every page (about 1 s of bear's 13). Keeping them on the heap, and the heap from shrinking,
  // reuses the pages.
  mallopt(M_MMAP_MAX, 0);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
#endif
  morphmill::record_command_line(argc, argv);
  CLI::App app{
      "morphmill: compute what a milling tool leaves of a part, exactly, and measure how exact it is.\n"
      "Every command takes a job file (JSON, see docs/job-format.md) or meshes (PLY, STL, OBJ).\n"
      "Run 'morphmill COMMAND --help' for the options of each command."};
  app.set_version_flag("--version", std::string("morphmill ") + MORPHMILL_VERSION);
  app.require_subcommand(1);
  app.fallthrough();  // so that --strict may follow the command's own arguments
  app.add_flag("--strict", morphmill::strict_warnings(),
               "Refuse (exit 2) a job that has any warning (unknown keys, ignored G-code words)");
  morphmill::register_info_commands(app);
  morphmill::register_erode_command(app);
  morphmill::register_reference_command(app);
  morphmill::register_deviation_commands(app);
  morphmill::register_verify_command(app);
  morphmill::register_compare_command(app);
  morphmill::register_stress_command(app);
  morphmill::register_study_command(app);
  morphmill::register_planar_commands(app);
  morphmill::register_completion_command(app);
  morphmill::add_global_options(app);
  // Every command's own work runs in its callback, after this: the thread cap applies to it.
  app.parse_complete_callback(morphmill::apply_global_thread_limit);
  const std::vector<std::string> arguments = morphmill::normalized_arguments(argc, argv);
  try {
    // CLI11 takes the arguments last first.
    app.parse(std::vector<std::string>(arguments.rbegin(), arguments.rend()));
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    if (code != 0) {
      const std::string suggestion = morphmill::suggestion_for(app, arguments);
      if (!suggestion.empty()) std::cerr << "morphmill: " << suggestion << '\n';
    }
    return code == 0 ? morphmill::kExitOk : morphmill::kExitBadInput;
  } catch (const morphmill::VerdictFailed&) {
    return morphmill::kExitVerdictFails;
  } catch (const morphmill::CampaignIncomplete&) {
    return morphmill::kExitIncomplete;
  } catch (const morph::InputError& e) {
    std::cerr << "morphmill: error: " << e.what() << '\n';
    return morphmill::kExitBadInput;
  } catch (const morph::IoError& e) {
    std::cerr << "morphmill: error: " << e.what() << '\n';
    return morphmill::kExitBadInput;
  } catch (const morph::LimitError& e) {
    std::cerr << "morphmill: error: " << e.what() << '\n';
    return morphmill::kExitBadInput;
  } catch (const std::exception& e) {
    std::cerr << "morphmill: internal error: " << e.what() << '\n';
    return morphmill::kExitInternal;
  }
  return morphmill::kExitOk;
}
