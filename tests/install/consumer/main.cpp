// Lists the jobs of the tesserad at argv[1] through the installed client library: one line
// "jobs: N", then "ID STATE" per job.
#include <client/client.hpp>

#include <iostream>

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: tessera_consumer HOST:PORT\n";
    return 2;
  }
  try {
    tessera::Client client(tessera::ClientOptions{.target = argv[1]});
    const std::vector<tessera::v1::Job> jobs = client.list();
    std::cout << "jobs: " << jobs.size() << '\n';
    for (const tessera::v1::Job& job : jobs)
      std::cout << job.id() << ' ' << tessera::v1::JobState_Name(job.state()) << '\n';
  } catch (const tessera::ClientError& e) {
    std::cerr << "tessera_consumer: " << e.what() << '\n';
    return 1;
  }
  return 0;
}
