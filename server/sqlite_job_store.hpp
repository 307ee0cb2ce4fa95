#pragma once
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <utility>

#include "server/job_store.hpp"

namespace SQLite {
class Database;
}

namespace tessera::server {

// The embedded job store: one SQLite database file in WAL mode with synchronous=FULL, so
// every committed job and tile survives a kill -9 or a power cut. One connection behind a
// mutex: the daemon's writes are a few per tile, far below what one connection sustains.
//
// Tile claims live in memory here, not in the file: only this process works on the
// database, and a restarted process has no live claims to honour (they lapsed with the
// process that held them). A store shared by several daemons keeps them as rows instead.
class SqliteJobStore final : public JobStore {
 public:
  // Opens or creates the database at `path`; ":memory:" gives a private database that
  // lives as long as this object (in-process daemons without a data directory, tests).
  // Throws std::runtime_error naming the file when it cannot be opened or is not a job
  // store of a known schema version.
  explicit SqliteJobStore(const std::filesystem::path& path);
  ~SqliteJobStore() override;

  JobRecord create_job(const JobRecord& job, const SceneSource& scene) override;
  std::optional<JobRecord> find_job(std::string_view id) const override;
  std::optional<JobRecord> find_job_by_request(std::string_view submitter,
                                               std::string_view request_id) const override;
  std::vector<JobRecord> list_jobs(const JobQuery& query) const override;
  std::vector<JobRecord> unfinished_jobs() const override;
  std::optional<SceneSource> scene(std::string_view id) const override;
  std::size_t unfinished_count(std::string_view submitter) const override;
  std::map<JobState, std::size_t> count_by_state() const override;
  std::optional<JobRecord> add_prepare_time(std::string_view id, std::int64_t prepare_ms) override;
  std::optional<JobRecord> mark_running(std::string_view id, std::int64_t now_ms) override;
  std::optional<JobRecord> finish_job(std::string_view id, JobState state,
                                      const std::string& message, std::int64_t now_ms) override;
  std::optional<JobRecord> pause_job(std::string_view id) override;
  std::optional<JobRecord> resume_job(std::string_view id) override;
  std::optional<JobRecord> retry_job(std::string_view id) override;
  std::optional<JobRecord> update_job(std::string_view id, const JobUpdate& update) override;
  std::uint32_t record_tile_failure(std::string_view id, std::uint32_t index) override;
  bool claim_tile(std::string_view id, std::uint32_t index, std::string_view owner,
                  std::int64_t lease_until_ms, std::int64_t now_ms) override;
  void release_tile(std::string_view id, std::uint32_t index, std::string_view owner) override;
  TileCommitResult commit_tile(std::string_view id, std::uint32_t index, std::string_view owner,
                               const std::vector<std::uint8_t>& exr, std::uint64_t rays,
                               std::int64_t now_ms) override;
  TileCommitResult commit_tile_pass(std::string_view id, std::uint32_t index,
                                    std::string_view owner, const std::vector<std::uint8_t>& exr,
                                    std::uint64_t rays, std::int64_t now_ms,
                                    const TilePassState& state, bool last_pass) override;
  std::optional<TilePassState> tile_pass_state(std::string_view id,
                                               std::uint32_t tile) const override;
  std::vector<std::uint32_t> stored_tile_indices(std::string_view id) const override;
  std::vector<StoredTile> tiles_after(std::string_view id, std::uint32_t after_ordinal,
                                      std::size_t limit) const override;
  std::uint32_t tile_commit_count(std::string_view id, std::uint32_t index) const override;
  bool delete_job(std::string_view id) override;
  std::vector<std::string> apply_retention(const RetentionPolicy& policy,
                                           std::int64_t now_ms) override;

  // The file name tesserad uses inside its data directory.
  static constexpr const char* kFileName = "jobs.sqlite3";

 private:
  struct Claim {
    std::string owner;
    std::int64_t lease_until_ms = 0;
  };

  std::optional<JobRecord> find_locked(std::string_view id) const;
  std::optional<JobRecord> find_by_request_locked(std::string_view submitter,
                                                  std::string_view request_id) const;
  TileCommitResult commit_locked(std::string_view id, std::uint32_t index, std::string_view owner,
                                 const std::vector<std::uint8_t>& exr, std::uint64_t rays,
                                 std::int64_t now_ms, const TilePassState* state, bool last_pass);
  bool delete_locked(std::string_view id);
  // Moves a job in one of `from_states` (an SQL condition on `state`) to `to`; `reopen`
  // also clears its error, finish time and tile failure counts (a retried job).
  std::optional<JobRecord> change_state(std::string_view id, const std::string& from_states,
                                        JobState to, bool reopen);

  mutable std::mutex mutex_;
  std::unique_ptr<SQLite::Database> db_;
  std::map<std::pair<std::string, std::uint32_t>, Claim, std::less<>> claims_;
};

}  // namespace tessera::server
