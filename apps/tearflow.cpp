// tearflow: the command-line program. Subcommands are added by the modules that own them.
#include <CLI/CLI.hpp>

int main(int argc, char** argv) {
  CLI::App app{"tearflow: blood flow and pressure in type B aortic dissection"};
  app.require_subcommand(1);
  CLI11_PARSE(app, argc, argv);
  return 0;
}
