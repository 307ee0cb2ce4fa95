#include "server/sqlite_job_store.hpp"

#include <SQLiteCpp/SQLiteCpp.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <limits>

#include "convert/scene_proto.hpp"

namespace tessera::server {
namespace {

// PRAGMA user_version of the schema below; a file with another version is refused rather
// than misread. Version 2 added tile_states (progressive passes), job_labels and
// tile_failures (job control): tables only, so a version 1 file is upgraded in place by
// creating them. Version 3 added job_requests (idempotent SubmitJob; created like the
// others, an older file's jobs simply have no request id) and jobs.prepare_ms (rays per
// second without the scene preparation), added to an older file's jobs table with its
// default.
constexpr int kSchemaVersion = 3;
constexpr int kOldestUpgradableVersion = 1;

// Tiles reference jobs by their integer sequence, not the id text, to keep the tile index
// small. Scenes are stored once per distinct content (scene_key) and shared.
constexpr const char* kSchema = R"sql(
CREATE TABLE IF NOT EXISTS scenes (
  scene_key TEXT PRIMARY KEY,
  scene BLOB NOT NULL
);
CREATE TABLE IF NOT EXISTS jobs (
  sequence INTEGER PRIMARY KEY AUTOINCREMENT,
  id TEXT NOT NULL UNIQUE,
  name TEXT NOT NULL,
  submitter TEXT NOT NULL,
  priority INTEGER NOT NULL,
  state INTEGER NOT NULL,
  settings BLOB NOT NULL,
  scene_key TEXT NOT NULL REFERENCES scenes(scene_key),
  tiles_total INTEGER NOT NULL,
  tiles_done INTEGER NOT NULL DEFAULT 0,
  rays_traced INTEGER NOT NULL DEFAULT 0,
  error TEXT NOT NULL DEFAULT '',
  cancel_reason TEXT NOT NULL DEFAULT '',
  submitted_ms INTEGER NOT NULL,
  started_ms INTEGER NOT NULL DEFAULT 0,
  finished_ms INTEGER NOT NULL DEFAULT 0,
  prepare_ms INTEGER NOT NULL DEFAULT 0
);
CREATE INDEX IF NOT EXISTS jobs_by_state ON jobs(state, sequence);
CREATE INDEX IF NOT EXISTS jobs_by_scene ON jobs(scene_key);
CREATE INDEX IF NOT EXISTS jobs_by_submitter ON jobs(submitter, state);
CREATE TABLE IF NOT EXISTS tiles (
  job_sequence INTEGER NOT NULL REFERENCES jobs(sequence) ON DELETE CASCADE,
  tile_index INTEGER NOT NULL,
  ordinal INTEGER NOT NULL,
  rays_after INTEGER NOT NULL,
  finished_ms INTEGER NOT NULL,
  commits INTEGER NOT NULL DEFAULT 1,
  exr BLOB NOT NULL,
  PRIMARY KEY (job_sequence, tile_index)
);
CREATE UNIQUE INDEX IF NOT EXISTS tiles_by_ordinal ON tiles(job_sequence, ordinal);
-- Jobs with progressive passes store each pass of a tile as a row of tiles (index pass-major,
-- server/job_passes.hpp) and, between a tile's passes, its accumulated state here: one row
-- per tile, replaced by each pass and dropped with the last.
CREATE TABLE IF NOT EXISTS tile_states (
  job_sequence INTEGER NOT NULL REFERENCES jobs(sequence) ON DELETE CASCADE,
  tile INTEGER NOT NULL,
  passes_done INTEGER NOT NULL,
  state BLOB NOT NULL,
  PRIMARY KEY (job_sequence, tile)
);
CREATE TABLE IF NOT EXISTS job_labels (
  job_sequence INTEGER NOT NULL REFERENCES jobs(sequence) ON DELETE CASCADE,
  key TEXT NOT NULL,
  value TEXT NOT NULL,
  PRIMARY KEY (job_sequence, key)
);
CREATE INDEX IF NOT EXISTS job_labels_by_key ON job_labels(key, value);
CREATE TABLE IF NOT EXISTS tile_failures (
  job_sequence INTEGER NOT NULL REFERENCES jobs(sequence) ON DELETE CASCADE,
  tile_index INTEGER NOT NULL,
  failures INTEGER NOT NULL,
  PRIMARY KEY (job_sequence, tile_index)
);
-- SubmitJobRequest.request_id: the submitter is the one at submission (UpdateJob may change
-- the job's later), so a retry finds its job whatever happened to it since. Deleting the job
-- frees the id.
CREATE TABLE IF NOT EXISTS job_requests (
  submitter TEXT NOT NULL,
  request_id TEXT NOT NULL,
  job_sequence INTEGER NOT NULL UNIQUE REFERENCES jobs(sequence) ON DELETE CASCADE,
  fingerprint TEXT NOT NULL,
  PRIMARY KEY (submitter, request_id)
);
)sql";

constexpr const char* kJobColumns =
    "sequence, id, name, priority, state, settings, tiles_total, tiles_done, rays_traced, "
    "error, cancel_reason, submitted_ms, started_ms, finished_ms, submitter, prepare_ms, "
    "(SELECT request_id FROM job_requests WHERE job_sequence = jobs.sequence), "
    "(SELECT fingerprint FROM job_requests WHERE job_sequence = jobs.sequence)";

JobRecord read_job(SQLite::Statement& q) {
  JobRecord r;
  r.sequence = q.getColumn(0).getInt64();
  r.id = q.getColumn(1).getString();
  r.name = q.getColumn(2).getString();
  r.priority = q.getColumn(3).getInt();
  const int state = q.getColumn(4).getInt();
  if (state < 0 || state > static_cast<int>(JobState::kPaused))
    throw std::runtime_error("job " + r.id + " has an unknown state " + std::to_string(state));
  r.state = static_cast<JobState>(state);
  v1::RenderSettings settings;
  const SQLite::Column blob = q.getColumn(5);
  if (!settings.ParseFromArray(blob.getBlob(), blob.getBytes()))
    throw std::runtime_error("job " + r.id + " has unreadable render settings");
  r.settings = settings_from_proto(settings);
  r.tiles_total = static_cast<std::uint32_t>(q.getColumn(6).getInt64());
  r.tiles_done = static_cast<std::uint32_t>(q.getColumn(7).getInt64());
  r.rays_traced = static_cast<std::uint64_t>(q.getColumn(8).getInt64());
  r.error = q.getColumn(9).getString();
  r.cancel_reason = q.getColumn(10).getString();
  r.submitted_unix_ms = q.getColumn(11).getInt64();
  r.started_unix_ms = q.getColumn(12).getInt64();
  r.finished_unix_ms = q.getColumn(13).getInt64();
  r.submitter = q.getColumn(14).getString();
  r.prepare_ms = q.getColumn(15).getInt64();
  // NULL (no request id) reads as "".
  r.request_id = q.getColumn(16).getString();
  r.request_fingerprint = q.getColumn(17).getString();
  return r;
}

void bind_text(SQLite::Statement& q, int index, std::string_view text) {
  q.bind(index, std::string(text));
}

void read_labels(SQLite::Database& db, JobRecord& job) {
  SQLite::Statement q(db, "SELECT key, value FROM job_labels WHERE job_sequence = ?");
  q.bind(1, job.sequence);
  job.labels.clear();
  while (q.executeStep())
    job.labels.emplace(q.getColumn(0).getString(), q.getColumn(1).getString());
}

void write_label(SQLite::Database& db, std::int64_t sequence, const std::string& key,
                 const std::string& value) {
  SQLite::Statement q(db,
                      "INSERT INTO job_labels(job_sequence, key, value) VALUES (?, ?, ?) "
                      "ON CONFLICT(job_sequence, key) DO UPDATE SET value = excluded.value");
  q.bind(1, sequence);
  q.bind(2, key);
  q.bind(3, value);
  q.exec();
}

// "state IN (...)" over the given states, as literals (they are our own enum values).
std::string state_in(std::initializer_list<JobState> states) {
  std::string sql = "state IN (";
  for (const JobState state : states) {
    if (sql.back() != '(') sql += ", ";
    sql += std::to_string(static_cast<int>(state));
  }
  return sql + ")";
}

// FNV-1a, 64 bits: a content key, not a security boundary. Two different scenes with the
// same key are told apart by comparing their bytes (see create_job).
std::string content_key(const std::string& bytes) {
  std::uint64_t hash = 0xcbf29ce484222325ull;
  for (const char c : bytes) {
    hash ^= static_cast<unsigned char>(c);
    hash *= 0x100000001b3ull;
  }
  char text[32];
  std::snprintf(text, sizeof text, "fnv1a64-%016llx-%zu", static_cast<unsigned long long>(hash),
                bytes.size());
  return text;
}

std::string scene_blob(const SceneSource& scene) {
  // One blob holding both messages, each prefixed with its length, so a scene is one row.
  std::string blob;
  const auto append = [&](const std::string& part) {
    const std::uint64_t size = part.size();
    blob.append(reinterpret_cast<const char*>(&size), sizeof size);
    blob.append(part);
  };
  append(scene.scene_proto);
  append(scene.settings_proto);
  return blob;
}

SceneSource parse_scene_blob(const std::string& blob) {
  SceneSource source;
  std::size_t at = 0;
  const auto take = [&](std::string& part) {
    std::uint64_t size = 0;
    if (blob.size() - at < sizeof size) throw std::runtime_error("truncated scene record");
    std::memcpy(&size, blob.data() + at, sizeof size);
    at += sizeof size;
    if (blob.size() - at < size) throw std::runtime_error("truncated scene record");
    part.assign(blob, at, size);
    at += size;
  };
  take(source.scene_proto);
  take(source.settings_proto);
  return source;
}

}  // namespace

SqliteJobStore::SqliteJobStore(const std::filesystem::path& path) {
  const std::string name = path.string();
  try {
    db_ = std::make_unique<SQLite::Database>(name, SQLite::OPEN_READWRITE | SQLite::OPEN_CREATE);
    db_->exec("PRAGMA busy_timeout = 5000");
    if (name != ":memory:") {
      // WAL: readers never block the writer, and a commit is one append. FULL syncs the
      // log on every commit, so nothing acknowledged is lost even to a power cut.
      db_->exec("PRAGMA journal_mode = WAL");
      db_->exec("PRAGMA synchronous = FULL");
    }
    db_->exec("PRAGMA foreign_keys = ON");
    const int version = db_->execAndGet("PRAGMA user_version").getInt();
    if (version != 0 && (version < kOldestUpgradableVersion || version > kSchemaVersion))
      throw std::runtime_error("schema version " + std::to_string(version) +
                               " is not the one this tesserad knows (" +
                               std::to_string(kSchemaVersion) + ")");
    SQLite::Transaction transaction(*db_);
    db_->exec(kSchema);
    // Columns added since version 1 (CREATE TABLE IF NOT EXISTS leaves an old table as is).
    bool has_prepare_ms = false;
    SQLite::Statement columns(*db_, "PRAGMA table_info(jobs)");
    while (columns.executeStep())
      if (columns.getColumn(1).getString() == "prepare_ms") has_prepare_ms = true;
    columns.reset();
    if (!has_prepare_ms)
      db_->exec("ALTER TABLE jobs ADD COLUMN prepare_ms INTEGER NOT NULL DEFAULT 0");
    db_->exec("PRAGMA user_version = " + std::to_string(kSchemaVersion));
    transaction.commit();
  } catch (const std::exception& e) {
    throw std::runtime_error("job store " + name + ": " + e.what());
  }
}

SqliteJobStore::~SqliteJobStore() = default;

JobRecord SqliteJobStore::create_job(const JobRecord& job, const SceneSource& scene) {
  std::lock_guard lock(mutex_);
  const std::string blob = scene_blob(scene);
  SQLite::Transaction transaction(*db_);
  {
    SQLite::Statement exists(*db_, "SELECT 1 FROM jobs WHERE id = ?");
    exists.bind(1, job.id);
    if (exists.executeStep()) throw DuplicateJobId("job id '" + job.id + "' is already in use");
  }
  if (!job.request_id.empty()) {
    if (auto existing = find_by_request_locked(job.submitter, job.request_id))
      throw RequestIdTaken(std::move(*existing));
  }
  std::string key = content_key(blob);
  {
    SQLite::Statement existing(*db_, "SELECT scene FROM scenes WHERE scene_key = ?");
    existing.bind(1, key);
    if (existing.executeStep()) {
      const SQLite::Column stored = existing.getColumn(0);
      const bool same = static_cast<std::size_t>(stored.getBytes()) == blob.size() &&
                        std::memcmp(stored.getBlob(), blob.data(), blob.size()) == 0;
      if (!same) key += "-" + job.id;  // a hash collision: this scene gets its own row
    }
  }
  {
    SQLite::Statement insert(*db_, "INSERT OR IGNORE INTO scenes(scene_key, scene) VALUES (?, ?)");
    insert.bind(1, key);
    insert.bind(2, blob.data(), static_cast<int>(blob.size()));
    insert.exec();
  }
  const std::string settings = settings_to_proto(job.settings).SerializeAsString();
  SQLite::Statement insert(*db_,
                           "INSERT INTO jobs(id, name, priority, state, settings, scene_key, "
                           "tiles_total, submitted_ms, submitter) VALUES (?, ?, ?, ?, ?, ?, ?, ?, "
                           "?)");
  insert.bind(1, job.id);
  insert.bind(2, job.name);
  insert.bind(3, job.priority);
  insert.bind(4, static_cast<int>(JobState::kQueued));
  insert.bind(5, settings.data(), static_cast<int>(settings.size()));
  insert.bind(6, key);
  insert.bind(7, static_cast<std::int64_t>(job.tiles_total));
  insert.bind(8, job.submitted_unix_ms);
  insert.bind(9, job.submitter);
  insert.exec();
  const std::int64_t sequence = db_->getLastInsertRowid();
  for (const auto& [key, value] : job.labels) write_label(*db_, sequence, key, value);
  if (!job.request_id.empty()) {
    SQLite::Statement request(*db_,
                              "INSERT INTO job_requests(submitter, request_id, job_sequence, "
                              "fingerprint) VALUES (?, ?, ?, ?)");
    request.bind(1, job.submitter);
    request.bind(2, job.request_id);
    request.bind(3, sequence);
    request.bind(4, job.request_fingerprint);
    request.exec();
  }
  transaction.commit();
  return *find_locked(job.id);
}

std::optional<JobRecord> SqliteJobStore::find_by_request_locked(std::string_view submitter,
                                                                std::string_view request_id) const {
  SQLite::Statement q(*db_, std::string("SELECT ") + kJobColumns +
                                " FROM jobs WHERE sequence = (SELECT job_sequence FROM "
                                "job_requests WHERE submitter = ? AND request_id = ?)");
  bind_text(q, 1, submitter);
  bind_text(q, 2, request_id);
  if (!q.executeStep()) return std::nullopt;
  JobRecord job = read_job(q);
  read_labels(*db_, job);
  return job;
}

std::optional<JobRecord> SqliteJobStore::find_job_by_request(std::string_view submitter,
                                                             std::string_view request_id) const {
  std::lock_guard lock(mutex_);
  return find_by_request_locked(submitter, request_id);
}

std::optional<JobRecord> SqliteJobStore::find_locked(std::string_view id) const {
  SQLite::Statement q(*db_, std::string("SELECT ") + kJobColumns + " FROM jobs WHERE id = ?");
  bind_text(q, 1, id);
  if (!q.executeStep()) return std::nullopt;
  JobRecord job = read_job(q);
  read_labels(*db_, job);
  return job;
}

std::optional<JobRecord> SqliteJobStore::find_job(std::string_view id) const {
  std::lock_guard lock(mutex_);
  return find_locked(id);
}

std::vector<JobRecord> SqliteJobStore::list_jobs(const JobQuery& query) const {
  std::lock_guard lock(mutex_);
  std::string sql = std::string("SELECT ") + kJobColumns + " FROM jobs WHERE sequence < ?";
  if (query.state) sql += " AND state = ?";
  if (query.submitter) sql += " AND submitter = ?";
  if (query.name) sql += " AND name = ?";
  if (query.label_key)
    sql += std::string(" AND sequence IN (SELECT job_sequence FROM job_labels WHERE key = ?") +
           (query.label_value ? " AND value = ?)" : ")");
  sql += " ORDER BY sequence DESC LIMIT ?";
  SQLite::Statement q(*db_, sql);
  int at = 1;
  q.bind(at++, query.before_sequence.value_or(std::numeric_limits<std::int64_t>::max()));
  if (query.state) q.bind(at++, static_cast<int>(*query.state));
  if (query.submitter) q.bind(at++, *query.submitter);
  if (query.name) q.bind(at++, *query.name);
  if (query.label_key) {
    q.bind(at++, *query.label_key);
    if (query.label_value) q.bind(at++, *query.label_value);
  }
  q.bind(at, static_cast<std::int64_t>(
                 std::min<std::size_t>(query.limit, std::numeric_limits<std::int64_t>::max())));
  std::vector<JobRecord> jobs;
  while (q.executeStep()) jobs.push_back(read_job(q));
  for (JobRecord& job : jobs) read_labels(*db_, job);
  return jobs;
}

std::vector<JobRecord> SqliteJobStore::unfinished_jobs() const {
  std::lock_guard lock(mutex_);
  SQLite::Statement q(*db_,
                      std::string("SELECT ") + kJobColumns + " FROM jobs WHERE " +
                          state_in({JobState::kQueued, JobState::kRunning, JobState::kPaused}) +
                          " ORDER BY sequence");
  std::vector<JobRecord> jobs;
  while (q.executeStep()) jobs.push_back(read_job(q));
  for (JobRecord& job : jobs) read_labels(*db_, job);
  return jobs;
}

std::optional<SceneSource> SqliteJobStore::scene(std::string_view id) const {
  std::lock_guard lock(mutex_);
  SQLite::Statement q(*db_,
                      "SELECT scenes.scene FROM jobs JOIN scenes USING (scene_key) WHERE id = ?");
  bind_text(q, 1, id);
  if (!q.executeStep()) return std::nullopt;
  const SQLite::Column blob = q.getColumn(0);
  return parse_scene_blob(std::string(static_cast<const char*>(blob.getBlob()),
                                      static_cast<std::size_t>(blob.getBytes())));
}

std::size_t SqliteJobStore::unfinished_count(std::string_view submitter) const {
  std::lock_guard lock(mutex_);
  SQLite::Statement q(*db_,
                      "SELECT COUNT(*) FROM jobs WHERE submitter = ? AND " +
                          state_in({JobState::kQueued, JobState::kRunning, JobState::kPaused}));
  bind_text(q, 1, submitter);
  q.executeStep();
  return static_cast<std::size_t>(q.getColumn(0).getInt64());
}

std::optional<JobRecord> SqliteJobStore::add_prepare_time(std::string_view id,
                                                          std::int64_t prepare_ms) {
  std::lock_guard lock(mutex_);
  SQLite::Statement q(*db_, "UPDATE jobs SET prepare_ms = prepare_ms + ? WHERE id = ?");
  q.bind(1, prepare_ms);
  bind_text(q, 2, id);
  if (q.exec() == 0) return std::nullopt;
  return find_locked(id);
}

std::map<JobState, std::size_t> SqliteJobStore::count_by_state() const {
  std::lock_guard lock(mutex_);
  SQLite::Statement q(*db_, "SELECT state, COUNT(*) FROM jobs GROUP BY state");
  std::map<JobState, std::size_t> counts;
  while (q.executeStep()) {
    const int state = q.getColumn(0).getInt();
    if (state < 0 || state > static_cast<int>(JobState::kPaused)) continue;
    counts[static_cast<JobState>(state)] = static_cast<std::size_t>(q.getColumn(1).getInt64());
  }
  return counts;
}

std::optional<JobRecord> SqliteJobStore::mark_running(std::string_view id, std::int64_t now_ms) {
  std::lock_guard lock(mutex_);
  // started_ms keeps the first start: a job resumed after a restart has been running since.
  SQLite::Statement q(*db_,
                      "UPDATE jobs SET state = ?, started_ms = CASE WHEN started_ms = 0 THEN ? "
                      "ELSE started_ms END WHERE id = ? AND state IN (?, ?)");
  q.bind(1, static_cast<int>(JobState::kRunning));
  q.bind(2, now_ms);
  bind_text(q, 3, id);
  q.bind(4, static_cast<int>(JobState::kQueued));
  q.bind(5, static_cast<int>(JobState::kRunning));
  if (q.exec() == 0) return std::nullopt;
  return find_locked(id);
}

std::optional<JobRecord> SqliteJobStore::finish_job(std::string_view id, JobState state,
                                                    const std::string& message,
                                                    std::int64_t now_ms) {
  if (!is_finished(state)) throw std::invalid_argument("finish_job: not a final state");
  std::lock_guard lock(mutex_);
  SQLite::Statement q(*db_,
                      "UPDATE jobs SET state = ?, error = ?, cancel_reason = ?, finished_ms = ?, "
                      "started_ms = CASE WHEN started_ms = 0 THEN ? ELSE started_ms END "
                      "WHERE id = ? AND " +
                          state_in({JobState::kQueued, JobState::kRunning, JobState::kPaused}));
  q.bind(1, static_cast<int>(state));
  q.bind(2, state == JobState::kFailed ? message : std::string());
  q.bind(3, state == JobState::kCancelled ? message : std::string());
  q.bind(4, now_ms);
  q.bind(5, now_ms);
  bind_text(q, 6, id);
  if (q.exec() == 0) return std::nullopt;
  return find_locked(id);
}

bool SqliteJobStore::claim_tile(std::string_view id, std::uint32_t index, std::string_view owner,
                                std::int64_t lease_until_ms, std::int64_t now_ms) {
  std::lock_guard lock(mutex_);
  SQLite::Statement stored(*db_,
                           "SELECT 1 FROM tiles JOIN jobs ON tiles.job_sequence = jobs.sequence "
                           "WHERE jobs.id = ? AND tiles.tile_index = ?");
  bind_text(stored, 1, id);
  stored.bind(2, static_cast<std::int64_t>(index));
  if (stored.executeStep()) return false;
  const auto key = std::make_pair(std::string(id), index);
  const auto it = claims_.find(key);
  if (it != claims_.end() && it->second.owner != owner && it->second.lease_until_ms > now_ms)
    return false;
  claims_[key] = Claim{std::string(owner), lease_until_ms};
  return true;
}

void SqliteJobStore::release_tile(std::string_view id, std::uint32_t index,
                                  std::string_view owner) {
  std::lock_guard lock(mutex_);
  const auto it = claims_.find(std::make_pair(std::string(id), index));
  if (it != claims_.end() && it->second.owner == owner) claims_.erase(it);
}

TileCommitResult SqliteJobStore::commit_tile(std::string_view id, std::uint32_t index,
                                             std::string_view owner,
                                             const std::vector<std::uint8_t>& exr,
                                             std::uint64_t rays, std::int64_t now_ms) {
  std::lock_guard lock(mutex_);
  return commit_locked(id, index, owner, exr, rays, now_ms, nullptr, false);
}

TileCommitResult SqliteJobStore::commit_tile_pass(std::string_view id, std::uint32_t index,
                                                  std::string_view owner,
                                                  const std::vector<std::uint8_t>& exr,
                                                  std::uint64_t rays, std::int64_t now_ms,
                                                  const TilePassState& state, bool last_pass) {
  std::lock_guard lock(mutex_);
  return commit_locked(id, index, owner, exr, rays, now_ms, &state, last_pass);
}

std::optional<TilePassState> SqliteJobStore::tile_pass_state(std::string_view id,
                                                             std::uint32_t tile) const {
  std::lock_guard lock(mutex_);
  SQLite::Statement q(
      *db_,
      "SELECT tile_states.passes_done, tile_states.state FROM tile_states JOIN jobs ON "
      "tile_states.job_sequence = jobs.sequence WHERE jobs.id = ? AND tile_states.tile = ?");
  bind_text(q, 1, id);
  q.bind(2, static_cast<std::int64_t>(tile));
  if (!q.executeStep()) return std::nullopt;
  TilePassState state;
  state.tile = tile;
  state.passes_done = static_cast<std::uint32_t>(q.getColumn(0).getInt64());
  const SQLite::Column blob = q.getColumn(1);
  const auto* bytes = static_cast<const std::uint8_t*>(blob.getBlob());
  state.bytes.assign(bytes, bytes + blob.getBytes());
  return state;
}

TileCommitResult SqliteJobStore::commit_locked(std::string_view id, std::uint32_t index,
                                               std::string_view owner,
                                               const std::vector<std::uint8_t>& exr,
                                               std::uint64_t rays, std::int64_t now_ms,
                                               const TilePassState* state, bool last_pass) {
  const auto claim = claims_.find(std::make_pair(std::string(id), index));
  if (claim != claims_.end() && claim->second.owner == owner) claims_.erase(claim);

  TileCommitResult result;
  SQLite::Transaction transaction(*db_);
  std::optional<JobRecord> job = find_locked(id);
  if (!job) return result;
  result.job = *job;
  {
    // Counted even when the job is no longer running: a second render is what the counter
    // exists to reveal.
    SQLite::Statement again(*db_,
                            "UPDATE tiles SET commits = commits + 1 WHERE job_sequence = ? AND "
                            "tile_index = ?");
    again.bind(1, job->sequence);
    again.bind(2, static_cast<std::int64_t>(index));
    if (again.exec() > 0) {
      transaction.commit();
      result.outcome = TileCommit::kDuplicate;
      return result;
    }
  }
  if (job->state != JobState::kRunning && job->state != JobState::kPaused) return result;
  if (index >= job->tiles_total)
    throw std::out_of_range("tile " + std::to_string(index) + " of job " + job->id +
                            " is outside its " + std::to_string(job->tiles_total) + " tiles");
  const std::uint32_t ordinal = job->tiles_done + 1;
  const std::uint64_t rays_after = job->rays_traced + rays;
  const bool last = ordinal >= job->tiles_total;
  {
    SQLite::Statement insert(*db_,
                             "INSERT INTO tiles(job_sequence, tile_index, ordinal, rays_after, "
                             "finished_ms, exr) VALUES (?, ?, ?, ?, ?, ?)");
    insert.bind(1, job->sequence);
    insert.bind(2, static_cast<std::int64_t>(index));
    insert.bind(3, static_cast<std::int64_t>(ordinal));
    insert.bind(4, static_cast<std::int64_t>(rays_after));
    insert.bind(5, now_ms);
    insert.bind(6, exr.data(), static_cast<int>(exr.size()));
    insert.exec();
  }
  {
    SQLite::Statement update(*db_,
                             "UPDATE jobs SET tiles_done = ?, rays_traced = ?, state = ?, "
                             "finished_ms = ? WHERE sequence = ?");
    update.bind(1, static_cast<std::int64_t>(ordinal));
    update.bind(2, static_cast<std::int64_t>(rays_after));
    update.bind(3, static_cast<int>(last ? JobState::kCompleted : job->state));
    update.bind(4, last ? now_ms : std::int64_t{0});
    update.bind(5, job->sequence);
    update.exec();
  }
  if (state && last_pass) {
    SQLite::Statement drop(*db_, "DELETE FROM tile_states WHERE job_sequence = ? AND tile = ?");
    drop.bind(1, job->sequence);
    drop.bind(2, static_cast<std::int64_t>(state->tile));
    drop.exec();
  } else if (state) {
    SQLite::Statement keep(*db_,
                           "INSERT OR REPLACE INTO tile_states(job_sequence, tile, passes_done, "
                           "state) VALUES (?, ?, ?, ?)");
    keep.bind(1, job->sequence);
    keep.bind(2, static_cast<std::int64_t>(state->tile));
    keep.bind(3, static_cast<std::int64_t>(state->passes_done));
    keep.bind(4, state->bytes.data(), static_cast<int>(state->bytes.size()));
    keep.exec();
  }
  transaction.commit();
  result.outcome = last ? TileCommit::kCompletedJob : TileCommit::kStored;
  result.job = *find_locked(id);
  return result;
}

std::optional<JobRecord> SqliteJobStore::change_state(std::string_view id,
                                                      const std::string& from_states, JobState to,
                                                      bool reopen) {
  std::lock_guard lock(mutex_);
  SQLite::Transaction transaction(*db_);
  SQLite::Statement q(*db_,
                      std::string("UPDATE jobs SET state = ?") +
                          (reopen ? ", error = '', cancel_reason = '', finished_ms = 0" : "") +
                          " WHERE id = ? AND " + from_states);
  q.bind(1, static_cast<int>(to));
  bind_text(q, 2, id);
  if (q.exec() == 0) return std::nullopt;
  if (reopen) {
    SQLite::Statement failures(*db_,
                               "DELETE FROM tile_failures WHERE job_sequence = (SELECT sequence "
                               "FROM jobs WHERE id = ?)");
    bind_text(failures, 1, id);
    failures.exec();
  }
  transaction.commit();
  return find_locked(id);
}

std::optional<JobRecord> SqliteJobStore::pause_job(std::string_view id) {
  return change_state(id, state_in({JobState::kQueued, JobState::kRunning}), JobState::kPaused,
                      false);
}

std::optional<JobRecord> SqliteJobStore::resume_job(std::string_view id) {
  return change_state(id, state_in({JobState::kPaused}), JobState::kQueued, false);
}

std::optional<JobRecord> SqliteJobStore::retry_job(std::string_view id) {
  return change_state(id, state_in({JobState::kFailed, JobState::kCancelled}), JobState::kQueued,
                      true);
}

std::optional<JobRecord> SqliteJobStore::update_job(std::string_view id, const JobUpdate& update) {
  std::lock_guard lock(mutex_);
  SQLite::Transaction transaction(*db_);
  std::optional<JobRecord> job = find_locked(id);
  if (!job) return std::nullopt;
  if (update.priority) {
    SQLite::Statement q(*db_, "UPDATE jobs SET priority = ? WHERE sequence = ?");
    q.bind(1, *update.priority);
    q.bind(2, job->sequence);
    q.exec();
  }
  if (update.submitter) {
    SQLite::Statement q(*db_, "UPDATE jobs SET submitter = ? WHERE sequence = ?");
    q.bind(1, *update.submitter);
    q.bind(2, job->sequence);
    q.exec();
  }
  for (const std::string& key : update.remove_labels) {
    SQLite::Statement q(*db_, "DELETE FROM job_labels WHERE job_sequence = ? AND key = ?");
    q.bind(1, job->sequence);
    q.bind(2, key);
    q.exec();
  }
  for (const auto& [key, value] : update.set_labels) write_label(*db_, job->sequence, key, value);
  transaction.commit();
  return find_locked(id);
}

std::uint32_t SqliteJobStore::record_tile_failure(std::string_view id, std::uint32_t index) {
  std::lock_guard lock(mutex_);
  SQLite::Transaction transaction(*db_);
  SQLite::Statement q(*db_,
                      "INSERT INTO tile_failures(job_sequence, tile_index, failures) SELECT "
                      "sequence, ?, 1 FROM jobs WHERE id = ? ON CONFLICT(job_sequence, "
                      "tile_index) DO UPDATE SET failures = failures + 1");
  q.bind(1, static_cast<std::int64_t>(index));
  bind_text(q, 2, id);
  if (q.exec() == 0) return 0;
  SQLite::Statement count(*db_,
                          "SELECT failures FROM tile_failures JOIN jobs ON job_sequence = "
                          "sequence WHERE id = ? AND tile_index = ?");
  bind_text(count, 1, id);
  count.bind(2, static_cast<std::int64_t>(index));
  const std::uint32_t failures =
      count.executeStep() ? static_cast<std::uint32_t>(count.getColumn(0).getInt64()) : 0;
  transaction.commit();
  return failures;
}

std::vector<std::uint32_t> SqliteJobStore::stored_tile_indices(std::string_view id) const {
  std::lock_guard lock(mutex_);
  SQLite::Statement q(*db_,
                      "SELECT tile_index FROM tiles JOIN jobs ON tiles.job_sequence = "
                      "jobs.sequence WHERE jobs.id = ? ORDER BY tile_index");
  bind_text(q, 1, id);
  std::vector<std::uint32_t> indices;
  while (q.executeStep()) indices.push_back(static_cast<std::uint32_t>(q.getColumn(0).getInt64()));
  return indices;
}

std::vector<StoredTile> SqliteJobStore::tiles_after(std::string_view id,
                                                    std::uint32_t after_ordinal,
                                                    std::size_t limit) const {
  std::lock_guard lock(mutex_);
  SQLite::Statement q(*db_,
                      "SELECT tile_index, ordinal, rays_after, tiles.finished_ms, exr FROM tiles "
                      "JOIN jobs ON tiles.job_sequence = jobs.sequence WHERE jobs.id = ? AND "
                      "ordinal > ? ORDER BY ordinal LIMIT ?");
  bind_text(q, 1, id);
  q.bind(2, static_cast<std::int64_t>(after_ordinal));
  q.bind(3, static_cast<std::int64_t>(std::min<std::size_t>(limit, 1u << 30)));
  std::vector<StoredTile> tiles;
  while (q.executeStep()) {
    StoredTile tile;
    tile.index = static_cast<std::uint32_t>(q.getColumn(0).getInt64());
    tile.ordinal = static_cast<std::uint32_t>(q.getColumn(1).getInt64());
    tile.rays_after = static_cast<std::uint64_t>(q.getColumn(2).getInt64());
    tile.finished_unix_ms = q.getColumn(3).getInt64();
    const SQLite::Column blob = q.getColumn(4);
    const auto* bytes = static_cast<const std::uint8_t*>(blob.getBlob());
    tile.exr.assign(bytes, bytes + blob.getBytes());
    tiles.push_back(std::move(tile));
  }
  return tiles;
}

std::uint32_t SqliteJobStore::tile_commit_count(std::string_view id, std::uint32_t index) const {
  std::lock_guard lock(mutex_);
  SQLite::Statement q(*db_,
                      "SELECT commits FROM tiles JOIN jobs ON tiles.job_sequence = jobs.sequence "
                      "WHERE jobs.id = ? AND tile_index = ?");
  bind_text(q, 1, id);
  q.bind(2, static_cast<std::int64_t>(index));
  return q.executeStep() ? static_cast<std::uint32_t>(q.getColumn(0).getInt64()) : 0;
}

bool SqliteJobStore::delete_locked(std::string_view id) {
  SQLite::Statement key_of(
      *db_, "SELECT scene_key FROM jobs WHERE id = ? AND " +
                state_in({JobState::kCompleted, JobState::kFailed, JobState::kCancelled}));
  bind_text(key_of, 1, id);
  if (!key_of.executeStep()) return false;
  const std::string key = key_of.getColumn(0).getString();
  SQLite::Statement remove(*db_, "DELETE FROM jobs WHERE id = ?");
  bind_text(remove, 1, id);
  remove.exec();
  SQLite::Statement orphan(*db_,
                           "DELETE FROM scenes WHERE scene_key = ? AND NOT EXISTS (SELECT 1 FROM "
                           "jobs WHERE scene_key = ?)");
  orphan.bind(1, key);
  orphan.bind(2, key);
  orphan.exec();
  return true;
}

bool SqliteJobStore::delete_job(std::string_view id) {
  std::lock_guard lock(mutex_);
  SQLite::Transaction transaction(*db_);
  const bool deleted = delete_locked(id);
  transaction.commit();
  return deleted;
}

std::vector<std::string> SqliteJobStore::apply_retention(const RetentionPolicy& policy,
                                                         std::int64_t now_ms) {
  std::lock_guard lock(mutex_);
  std::vector<std::string> doomed;
  const auto finished_states = "state IN (" +
                               std::to_string(static_cast<int>(JobState::kCompleted)) + ", " +
                               std::to_string(static_cast<int>(JobState::kFailed)) + ", " +
                               std::to_string(static_cast<int>(JobState::kCancelled)) + ")";
  if (policy.ttl_ms > 0) {
    SQLite::Statement q(*db_, "SELECT id FROM jobs WHERE " + finished_states +
                                  " AND finished_ms < ? ORDER BY sequence");
    q.bind(1, now_ms - policy.ttl_ms);
    while (q.executeStep()) doomed.push_back(q.getColumn(0).getString());
  }
  if (policy.max_jobs > 0) {
    const auto total =
        static_cast<std::size_t>(db_->execAndGet("SELECT COUNT(*) FROM jobs").getInt64());
    const std::size_t remaining = total - doomed.size();
    if (remaining > policy.max_jobs) {
      // Oldest finished first (by when they finished), skipping those already doomed.
      SQLite::Statement q(*db_, "SELECT id FROM jobs WHERE " + finished_states +
                                    " ORDER BY finished_ms, sequence LIMIT ?");
      q.bind(1, static_cast<std::int64_t>(remaining - policy.max_jobs + doomed.size()));
      std::size_t extra = remaining - policy.max_jobs;
      while (extra > 0 && q.executeStep()) {
        std::string id = q.getColumn(0).getString();
        if (std::find(doomed.begin(), doomed.end(), id) != doomed.end()) continue;
        doomed.push_back(std::move(id));
        --extra;
      }
    }
  }
  if (doomed.empty()) return doomed;
  SQLite::Transaction transaction(*db_);
  for (const std::string& id : doomed) delete_locked(id);
  transaction.commit();
  return doomed;
}

}  // namespace tessera::server
