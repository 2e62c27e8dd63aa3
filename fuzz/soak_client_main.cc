// soak_client: one client process of `flsd bench soak`; prints its tally as one JSON object.

#include <CLI/CLI.hpp>

#include <cstdio>

#include "comm/security.h"
#include "fuzz/soak_client.h"

int main(int argc, char** argv) {
  CLI::App app{"soak_client: random requests to skilld, every reply checked against the contract"};
  flsd::fuzz::SoakClientOptions o;
  std::string security_file;
  bool light_maps = false, no_reset = false;
  app.add_option("--domain", o.domain_id, "DDS domain")->check(CLI::Range(0, 232));
  app.add_option("--partition", o.partition, "DDS partition")->required();
  app.add_option("--security", security_file, "DDS Security: a YAML file with a security: section");
  app.add_option("--name", o.name, "Prefix of its client ids");
  app.add_option("--seed", o.seed, "Seed of its requests");
  app.add_option("--seconds", o.seconds, "How long it runs")->check(CLI::Range(1.0, 86400.0));
  app.add_option("--rate", o.rate_hz, "Requests per second")->check(CLI::Range(1.0, 500.0));
  app.add_flag("--light-maps", light_maps, "Leave out the heavy maps");
  app.add_flag("--no-reset", no_reset, "The server cannot reset the robot (the hw backend)");
  app.add_option("--lease-timeout", o.lease_timeout, "The server's lease_timeout (s), from its config")
      ->required()
      ->check(CLI::PositiveNumber);
  app.add_option("--max-duration", o.max_duration, "The server's max_duration (s), from its config")
      ->required()
      ->check(CLI::PositiveNumber);
  CLI11_PARSE(app, argc, argv);
  o.heavy_maps = !light_maps;
  o.can_reset = !no_reset;
  try {
    if (!security_file.empty()) o.security = flsd::dds::LoadSecurityFile(security_file);
    std::printf("%s\n", flsd::fuzz::RunSoakClient(o).dump().c_str());
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "soak_client %s: %s\n", o.name.c_str(), e.what());
    return 1;
  }
}
