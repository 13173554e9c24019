#pragma once
// `trident stress`: the stress suite of issue 8 on the command line (src/stress/).
#include <memory>

namespace CLI {
class App;
}

namespace trident {

struct StressCommandOptions;

/// The subcommand's options, registered on the app; run() after parsing when parsed().
class StressCommand {
public:
    explicit StressCommand(CLI::App& app);
    ~StressCommand();

    bool parsed() const;
    /// Runs the suite, prints a row per case and configuration and a one-line summary; returns 0
    /// when nothing leaked or disagreed beyond tolerance, 1 otherwise. Throws std::invalid_argument
    /// on bad options.
    int run() const;

private:
    CLI::App* command_;
    std::unique_ptr<StressCommandOptions> options_;
};

}  // namespace trident
