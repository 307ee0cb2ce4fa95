#include "server/sqlite_job_store.hpp"

#include <gtest/gtest.h>
#include <sqlite3.h>

#include <unistd.h>
#include <filesystem>
#include <fstream>

#include "server/log_text.hpp"
#include "tests/support/test_dir.hpp"

namespace tessera::server {
namespace {

class SqliteJobStoreTest : public test::TestDirFixture {
 protected:
  SqliteJobStoreTest() : TestDirFixture("tesserad") {}

  std::filesystem::path file() const { return dir_ / SqliteJobStore::kFileName; }

  static JobRecord record(const std::string& id, std::uint32_t tiles = 4) {
    JobRecord r;
    r.id = id;
    r.name = "name of " + id;
    r.priority = 2;
    r.settings.width = 16;
    r.settings.height = 16;
    r.settings.tile_size = 8;
    r.settings.seed = 99;
    r.tiles_total = tiles;
    r.submitted_unix_ms = 1000;
    return r;
  }
  static SceneSource scene(const std::string& text = "scene") { return {text, "settings"}; }

  // Rows of a table, counted behind the store's back.
  std::int64_t rows(const std::string& table) const {
    sqlite3* db = nullptr;
    EXPECT_EQ(sqlite3_open(file().c_str(), &db), SQLITE_OK);
    sqlite3_stmt* q = nullptr;
    sqlite3_prepare_v2(db, ("SELECT COUNT(*) FROM " + table).c_str(), -1, &q, nullptr);
    sqlite3_step(q);
    const std::int64_t n = sqlite3_column_int64(q, 0);
    sqlite3_finalize(q);
    sqlite3_close(db);
    return n;
  }
};

// A pass of a tile and the tile's accumulated state are one transaction: the state is
// replaced by each pass, dropped with the last, and left alone by a duplicate or a job that
// is not running.
TEST_F(SqliteJobStoreTest, PassStatesAreReplacedPerPassAndDroppedWithTheLast) {
  SqliteJobStore store(file());
  store.create_job(record("job-a", 4), scene());  // 2 tiles x 2 passes
  store.mark_running("job-a", 1);
  EXPECT_FALSE(store.tile_pass_state("job-a", 1).has_value());
  const TilePassState first{1, 1, {1, 2, 3}};
  EXPECT_EQ(store.commit_tile_pass("job-a", 1, "w", {9}, 5, 2, first, false).outcome,
            TileCommit::kStored);
  auto state = store.tile_pass_state("job-a", 1);
  ASSERT_TRUE(state.has_value());
  EXPECT_EQ(state->passes_done, 1u);
  EXPECT_EQ(state->bytes, (std::vector<std::uint8_t>{1, 2, 3}));
  // A duplicate commit of that pass changes no state.
  EXPECT_EQ(
      store.commit_tile_pass("job-a", 1, "w", {9}, 5, 2, TilePassState{1, 1, {7}}, false).outcome,
      TileCommit::kDuplicate);
  EXPECT_EQ(store.tile_pass_state("job-a", 1)->bytes, (std::vector<std::uint8_t>{1, 2, 3}));
  store.commit_tile_pass("job-a", 0, "w", {9}, 5, 3, TilePassState{0, 1, {4}}, false);
  EXPECT_EQ(rows("tile_states"), 2);
  // Pass 2 of tile 1 (store index 3) is its last: its state goes in the same commit.
  EXPECT_EQ(
      store.commit_tile_pass("job-a", 3, "w", {9}, 5, 4, TilePassState{1, 2, {}}, true).outcome,
      TileCommit::kStored);
  EXPECT_FALSE(store.tile_pass_state("job-a", 1).has_value());
  EXPECT_EQ(store.tile_pass_state("job-a", 0)->passes_done, 1u);
  EXPECT_EQ(rows("tile_states"), 1);
  // Deleting the job deletes its states.
  store.finish_job("job-a", JobState::kCancelled, "", 5);
  EXPECT_EQ(
      store.commit_tile_pass("job-a", 2, "w", {9}, 5, 6, TilePassState{0, 2, {}}, true).outcome,
      TileCommit::kJobNotRunning);
  EXPECT_EQ(rows("tile_states"), 1);
  EXPECT_TRUE(store.delete_job("job-a"));
  EXPECT_EQ(rows("tile_states"), 0);
}

// A version-1 file (before passes) opens and gains the tile_states table.
TEST_F(SqliteJobStoreTest, AVersionOneFileGainsTheTileStatesTable) {
  {
    SqliteJobStore store(file());
    store.create_job(record("job-a"), scene());
  }
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(file().c_str(), &db), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(db, "DROP TABLE tile_states; PRAGMA user_version = 1", nullptr, nullptr,
                         nullptr),
            SQLITE_OK);
  sqlite3_close(db);
  SqliteJobStore store(file());
  EXPECT_TRUE(store.find_job("job-a").has_value());
  EXPECT_EQ(rows("tile_states"), 0);
}

TEST_F(SqliteJobStoreTest, JobsTilesAndScenesSurviveReopening) {
  {
    SqliteJobStore store(file());
    const JobRecord created = store.create_job(record("job-a"), scene("the scene"));
    EXPECT_GT(created.sequence, 0);
    EXPECT_EQ(created.state, JobState::kQueued);
    EXPECT_EQ(created.settings, record("job-a").settings);
    ASSERT_TRUE(store.mark_running("job-a", 2000));
    EXPECT_TRUE(store.claim_tile("job-a", 2, "w", 1'000'000, 2000));
    const TileCommitResult commit = store.commit_tile("job-a", 2, "w", {5, 6, 7}, 40, 2500);
    EXPECT_EQ(commit.outcome, TileCommit::kStored);
    EXPECT_EQ(commit.job.tiles_done, 1u);
    EXPECT_EQ(commit.job.rays_traced, 40u);
  }
  SqliteJobStore reopened(file());
  const auto unfinished = reopened.unfinished_jobs();
  ASSERT_EQ(unfinished.size(), 1u);
  const JobRecord& job = unfinished[0];
  EXPECT_EQ(job.id, "job-a");
  EXPECT_EQ(job.name, "name of job-a");
  EXPECT_EQ(job.priority, 2);
  EXPECT_EQ(job.state, JobState::kRunning);
  EXPECT_EQ(job.started_unix_ms, 2000);
  EXPECT_EQ(job.settings.seed, 99u);
  EXPECT_EQ(reopened.stored_tile_indices("job-a"), std::vector<std::uint32_t>{2});
  const auto tiles = reopened.tiles_after("job-a", 0, 10);
  ASSERT_EQ(tiles.size(), 1u);
  EXPECT_EQ(tiles[0].exr, (std::vector<std::uint8_t>{5, 6, 7}));
  EXPECT_EQ(tiles[0].ordinal, 1u);
  EXPECT_EQ(tiles[0].rays_after, 40u);
  EXPECT_EQ(tiles[0].finished_unix_ms, 2500);
  const auto source = reopened.scene("job-a");
  ASSERT_TRUE(source);
  EXPECT_EQ(source->scene_proto, "the scene");
  EXPECT_EQ(source->settings_proto, "settings");
  EXPECT_FALSE(reopened.scene("job-b"));
}

TEST_F(SqliteJobStoreTest, ATileIsStoredOnceAndARepeatIsCounted) {
  SqliteJobStore store(file());
  store.create_job(record("job-a", 2), scene());
  EXPECT_EQ(store.commit_tile("job-a", 0, "w", {1}, 1, 1).outcome, TileCommit::kJobNotRunning);
  store.mark_running("job-a", 1);
  EXPECT_EQ(store.commit_tile("job-a", 0, "w", {1}, 1, 1).outcome, TileCommit::kStored);
  EXPECT_FALSE(store.claim_tile("job-a", 0, "w", 100, 1));  // stored: nothing to claim
  EXPECT_EQ(store.commit_tile("job-a", 0, "w", {2}, 1, 1).outcome, TileCommit::kDuplicate);
  EXPECT_EQ(store.tile_commit_count("job-a", 0), 2u);
  EXPECT_EQ(store.tiles_after("job-a", 0, 10).at(0).exr, std::vector<std::uint8_t>{1});
  const TileCommitResult last = store.commit_tile("job-a", 1, "w", {3}, 1, 7);
  EXPECT_EQ(last.outcome, TileCommit::kCompletedJob);
  EXPECT_EQ(last.job.state, JobState::kCompleted);
  EXPECT_EQ(last.job.finished_unix_ms, 7);
  EXPECT_EQ(last.job.rays_traced, 2u);  // the repeat added nothing
  EXPECT_TRUE(store.unfinished_jobs().empty());
  EXPECT_THROW(store.create_job(record("job-a"), scene()), DuplicateJobId);
}

TEST_F(SqliteJobStoreTest, ClaimsBelongToOneOwnerUntilTheirLeaseLapses) {
  SqliteJobStore store(file());
  store.create_job(record("job-a"), scene());
  EXPECT_TRUE(store.claim_tile("job-a", 1, "one", 100, 10));
  EXPECT_TRUE(store.claim_tile("job-a", 1, "one", 200, 20));   // renewing
  EXPECT_FALSE(store.claim_tile("job-a", 1, "two", 300, 50));  // held by another
  EXPECT_TRUE(store.claim_tile("job-a", 1, "two", 300, 250));  // the lease lapsed
  store.release_tile("job-a", 1, "one");                       // not one's any more
  EXPECT_FALSE(store.claim_tile("job-a", 1, "one", 400, 260));
  store.release_tile("job-a", 1, "two");
  EXPECT_TRUE(store.claim_tile("job-a", 1, "one", 400, 260));
}

TEST_F(SqliteJobStoreTest, FinishingAppliesOnlyToUnfinishedJobs) {
  SqliteJobStore store(file());
  store.create_job(record("job-a"), scene());
  const auto cancelled = store.finish_job("job-a", JobState::kCancelled, "asked", 5);
  ASSERT_TRUE(cancelled);
  EXPECT_EQ(cancelled->cancel_reason, "asked");
  EXPECT_EQ(cancelled->error, "");
  EXPECT_FALSE(store.finish_job("job-a", JobState::kFailed, "late", 6));
  EXPECT_FALSE(store.mark_running("job-a", 6));
  EXPECT_FALSE(store.mark_running("job-x", 6));
  EXPECT_EQ(store.find_job("job-a")->state, JobState::kCancelled);
}

TEST_F(SqliteJobStoreTest, ListsNewestFirstByPageAndState) {
  SqliteJobStore store(file());
  std::vector<std::int64_t> sequences;
  for (int i = 0; i < 5; ++i)
    sequences.push_back(store.create_job(record("job-" + std::to_string(i)), scene()).sequence);
  store.finish_job("job-1", JobState::kFailed, "x", 1);
  store.finish_job("job-3", JobState::kFailed, "x", 1);
  JobQuery query;
  query.limit = 2;
  auto page = store.list_jobs(query);
  ASSERT_EQ(page.size(), 2u);
  EXPECT_EQ(page[0].id, "job-4");
  EXPECT_EQ(page[1].id, "job-3");
  query.before_sequence = page[1].sequence;
  page = store.list_jobs(query);
  ASSERT_EQ(page.size(), 2u);
  EXPECT_EQ(page[0].id, "job-2");
  EXPECT_EQ(page[1].id, "job-1");
  query = JobQuery{};
  query.state = JobState::kFailed;
  page = store.list_jobs(query);
  ASSERT_EQ(page.size(), 2u);
  EXPECT_EQ(page[0].id, "job-3");
  EXPECT_EQ(page[1].id, "job-1");
}

TEST_F(SqliteJobStoreTest, AScenePutTwiceIsStoredOnceAndOutlivesOneOfItsJobs) {
  SqliteJobStore store(file());
  store.create_job(record("job-a"), scene("shared"));
  store.create_job(record("job-b"), scene("shared"));
  store.create_job(record("job-c"), scene("other"));
  EXPECT_EQ(rows("scenes"), 2);
  EXPECT_FALSE(store.delete_job("job-a"));  // unfinished
  store.finish_job("job-a", JobState::kCancelled, "", 1);
  EXPECT_TRUE(store.delete_job("job-a"));
  EXPECT_FALSE(store.find_job("job-a"));
  EXPECT_EQ(store.scene("job-b")->scene_proto, "shared");
  EXPECT_EQ(rows("scenes"), 2);
  store.finish_job("job-b", JobState::kCancelled, "", 1);
  EXPECT_TRUE(store.delete_job("job-b"));
  EXPECT_EQ(rows("scenes"), 1);  // no job uses "shared" any more
  EXPECT_FALSE(store.delete_job("job-b"));
}

TEST_F(SqliteJobStoreTest, DeletingAJobDeletesItsTiles) {
  SqliteJobStore store(file());
  store.create_job(record("job-a", 1), scene());
  store.mark_running("job-a", 1);
  store.commit_tile("job-a", 0, "w", {1, 2}, 1, 2);
  EXPECT_EQ(rows("tiles"), 1);
  EXPECT_TRUE(store.delete_job("job-a"));
  EXPECT_EQ(rows("tiles"), 0);
}

TEST_F(SqliteJobStoreTest, RetentionDeletesOldFinishedJobsFirstAndNeverUnfinishedOnes) {
  SqliteJobStore store(file());
  for (int i = 0; i < 6; ++i) store.create_job(record("job-" + std::to_string(i)), scene());
  // job-0 stays queued; the others finish at times 100, 200, ... in reverse order of
  // submission, so "oldest finished" and "oldest submitted" disagree.
  for (int i = 1; i < 6; ++i)
    store.finish_job("job-" + std::to_string(i), JobState::kCancelled, "", 100 * (6 - i));
  // job_ttl: finished more than 250 ms before now (1000) are job-5 (100) and job-4 (200).
  auto deleted = store.apply_retention({750, 0}, 1000);
  EXPECT_EQ(deleted, (std::vector<std::string>{"job-4", "job-5"}));
  // max_jobs 2 of the 4 left: the oldest finished go, job-3 (300) then job-2 (400).
  deleted = store.apply_retention({0, 2}, 1000);
  EXPECT_EQ(deleted, (std::vector<std::string>{"job-3", "job-2"}));
  // max_jobs 0 of 2 would mean no limit; 1 deletes job-1 and never the queued job-0.
  EXPECT_TRUE(store.apply_retention({0, 0}, 1000).empty());
  EXPECT_EQ(store.apply_retention({0, 1}, 1000), std::vector<std::string>{"job-1"});
  EXPECT_TRUE(store.apply_retention({1, 0}, 1'000'000).empty());
  EXPECT_TRUE(store.find_job("job-0"));
}

TEST_F(SqliteJobStoreTest, AFileOfAnotherSchemaIsRefusedNamingIt) {
  {
    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open(file().c_str(), &db), SQLITE_OK);
    sqlite3_exec(db, "PRAGMA user_version = 42", nullptr, nullptr, nullptr);
    sqlite3_close(db);
  }
  try {
    SqliteJobStore store(file());
    FAIL() << "opened a store of schema version 42";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(file().string()), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("schema version 42"), std::string::npos) << e.what();
  }
  std::ofstream(dir_ / "garbage") << "this is not a database, just text long enough to tell";
  EXPECT_THROW(SqliteJobStore(dir_ / "garbage"), std::runtime_error);
}

TEST_F(SqliteJobStoreTest, PauseResumeAndRetryMoveOnlyFromTheirStates) {
  SqliteJobStore store(file());
  store.create_job(record("a"), scene());
  EXPECT_FALSE(store.resume_job("a"));  // queued: nothing to resume
  EXPECT_FALSE(store.retry_job("a"));   // unfinished: nothing to retry
  ASSERT_TRUE(store.pause_job("a"));
  EXPECT_EQ(store.find_job("a")->state, JobState::kPaused);
  EXPECT_FALSE(store.pause_job("a"));
  EXPECT_FALSE(store.mark_running("a", 5));  // a paused job is not picked up
  // A paused job is unfinished: resumed after a restart (as paused), counted for its
  // submitter, never deleted by retention.
  ASSERT_EQ(store.unfinished_jobs().size(), 1u);
  EXPECT_EQ(store.unfinished_count(""), 1u);
  RetentionPolicy policy;
  policy.ttl_ms = 1;
  EXPECT_TRUE(store.apply_retention(policy, 1'000'000).empty());
  // Tiles in flight when it was paused are kept.
  EXPECT_TRUE(store.claim_tile("a", 0, "w", 1'000'000, 10));
  EXPECT_EQ(store.commit_tile("a", 0, "w", {1, 2, 3}, 5, 20).outcome, TileCommit::kStored);
  EXPECT_EQ(store.find_job("a")->state, JobState::kPaused);

  ASSERT_TRUE(store.resume_job("a"));
  EXPECT_EQ(store.find_job("a")->state, JobState::kQueued);
  ASSERT_TRUE(store.finish_job("a", JobState::kCancelled, "by hand", 30));
  EXPECT_FALSE(store.pause_job("a"));
  const auto retried = store.retry_job("a");
  ASSERT_TRUE(retried);
  EXPECT_EQ(retried->state, JobState::kQueued);
  EXPECT_EQ(retried->cancel_reason, "");
  EXPECT_EQ(retried->finished_unix_ms, 0);
  EXPECT_EQ(retried->tiles_done, 1u);  // the tile is kept
  EXPECT_EQ(store.stored_tile_indices("a"), (std::vector<std::uint32_t>{0}));
}

TEST_F(SqliteJobStoreTest, LabelsAreStoredUpdatedAndFilter) {
  {
    SqliteJobStore store(file());
    JobRecord a = record("a");
    a.labels = {{"shot", "010"}, {"dept", "fx"}};
    store.create_job(a, scene());
    JobRecord b = record("b");
    b.name = "hero";
    b.labels = {{"shot", "020"}};
    store.create_job(b, scene());
    store.create_job(record("c"), scene());
  }
  SqliteJobStore store(file());  // labels survive reopening
  EXPECT_EQ(store.find_job("a")->labels, (JobLabels{{"dept", "fx"}, {"shot", "010"}}));
  const auto ids = [&](std::optional<std::string> name, std::optional<std::string> key,
                       std::optional<std::string> value = std::nullopt) {
    JobQuery query;
    query.name = std::move(name);
    query.label_key = std::move(key);
    query.label_value = std::move(value);
    std::vector<std::string> out;
    for (const JobRecord& job : store.list_jobs(query)) out.push_back(job.id);
    return out;
  };
  EXPECT_EQ(ids({}, "shot"), (std::vector<std::string>{"b", "a"}));
  EXPECT_EQ(ids({}, "shot", "010"), (std::vector<std::string>{"a"}));
  EXPECT_EQ(ids("hero", {}), (std::vector<std::string>{"b"}));
  EXPECT_EQ(ids("hero", "dept"), (std::vector<std::string>{}));

  JobUpdate update;
  update.priority = -4;
  update.submitter = "ana";
  update.remove_labels = {"dept"};
  update.set_labels = {{"shot", "030"}, {"take", "2"}};
  const auto updated = store.update_job("a", update);
  ASSERT_TRUE(updated);
  EXPECT_EQ(updated->priority, -4);
  EXPECT_EQ(updated->submitter, "ana");
  EXPECT_EQ(updated->labels, (JobLabels{{"shot", "030"}, {"take", "2"}}));
  EXPECT_FALSE(store.update_job("nope", update));
  // A deleted job takes its labels with it.
  ASSERT_TRUE(store.finish_job("a", JobState::kCompleted, "", 5));
  ASSERT_TRUE(store.delete_job("a"));
  EXPECT_EQ(rows("job_labels"), 1);
}

// A job store of schema version 1 (before labels and tile failure counts) is upgraded in
// place: its jobs are kept and the new tables created.
TEST_F(SqliteJobStoreTest, AVersionOneFileGainsLabelsAndFailureCounts) {
  {
    SqliteJobStore store(file());
    store.create_job(record("old"), scene());
  }
  {
    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open(file().c_str(), &db), SQLITE_OK);
    ASSERT_EQ(sqlite3_exec(db,
                           "DROP TABLE job_labels; DROP TABLE tile_failures; "
                           "PRAGMA user_version = 1",
                           nullptr, nullptr, nullptr),
              SQLITE_OK);
    sqlite3_close(db);
  }
  SqliteJobStore store(file());
  ASSERT_TRUE(store.find_job("old"));
  EXPECT_EQ(store.record_tile_failure("old", 1), 1u);
  JobUpdate update;
  update.set_labels = {{"k", "v"}};
  EXPECT_TRUE(store.update_job("old", update));
  EXPECT_EQ(store.find_job("old")->labels.at("k"), "v");
}

// A version-2 file (before prepare_ms) gains the column, its jobs reading 0.
TEST_F(SqliteJobStoreTest, AVersionTwoFileGainsThePreparationTime) {
  {
    SqliteJobStore store(file());
    store.create_job(record("old"), scene());
  }
  {
    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open(file().c_str(), &db), SQLITE_OK);
    ASSERT_EQ(sqlite3_exec(db, "ALTER TABLE jobs DROP COLUMN prepare_ms; PRAGMA user_version = 2",
                           nullptr, nullptr, nullptr),
              SQLITE_OK);
    sqlite3_close(db);
  }
  SqliteJobStore store(file());
  ASSERT_TRUE(store.find_job("old"));
  EXPECT_EQ(store.find_job("old")->prepare_ms, 0);
  EXPECT_EQ(store.add_prepare_time("old", 1500)->prepare_ms, 1500);
  EXPECT_EQ(store.add_prepare_time("old", 250)->prepare_ms, 1750);
  EXPECT_FALSE(store.add_prepare_time("nobody", 1));
}

TEST_F(SqliteJobStoreTest, CountsJobsByState) {
  SqliteJobStore store(file());
  EXPECT_TRUE(store.count_by_state().empty());
  store.create_job(record("a"), scene());
  store.create_job(record("b"), scene());
  store.create_job(record("c"), scene());
  ASSERT_TRUE(store.mark_running("b", 1));
  ASSERT_TRUE(store.finish_job("c", JobState::kCancelled, "", 2));
  const auto counts = store.count_by_state();
  EXPECT_EQ(counts.at(JobState::kQueued), 1u);
  EXPECT_EQ(counts.at(JobState::kRunning), 1u);
  EXPECT_EQ(counts.at(JobState::kCancelled), 1u);
  EXPECT_EQ(counts.count(JobState::kCompleted), 0u);
}

TEST(EscapeClientText, KeepsPrintableAsciiAndEscapesEverythingElse) {
  EXPECT_EQ(escape_client_text("plain name 1"), "plain name 1");
  EXPECT_EQ(escape_client_text("a\nb\r\x1b[31m"), "a\\x0ab\\x0d\\x1b[31m");
  EXPECT_EQ(escape_client_text("back\\slash"), "back\\\\slash");
  EXPECT_EQ(escape_client_text("caf\xc3\xa9"), "caf\\xc3\\xa9");
  EXPECT_EQ(escape_client_text("abcdef", 3), "abc...");
}

// A request id names one job per submitter while the job exists: taken ids are refused with
// the job they name, other submitters have their own ids, deleting the job frees the id,
// and all of it is in the file.
TEST_F(SqliteJobStoreTest, ARequestIdNamesOneJobOfItsSubmitterWhileTheJobExists) {
  JobRecord first = record("job-a");
  first.submitter = "alice";
  first.request_id = "req-1";
  first.request_fingerprint = "fp-1";
  {
    SqliteJobStore store(file());
    const JobRecord created = store.create_job(first, scene());
    EXPECT_EQ(created.request_id, "req-1");
    EXPECT_EQ(created.request_fingerprint, "fp-1");
    JobRecord again = record("job-b");
    again.submitter = "alice";
    again.request_id = "req-1";
    again.request_fingerprint = "fp-2";
    try {
      store.create_job(again, scene());
      ADD_FAILURE() << "a second job took request id req-1";
    } catch (const RequestIdTaken& e) {
      EXPECT_EQ(e.existing().id, "job-a");
      EXPECT_EQ(e.existing().request_fingerprint, "fp-1");
    }
    EXPECT_FALSE(store.find_job("job-b"));
    // Bob's req-1 is his own.
    again.submitter = "bob";
    EXPECT_EQ(store.create_job(again, scene()).request_id, "req-1");
    EXPECT_EQ(rows("jobs"), 2);
    // Jobs without a request id never collide on it.
    store.create_job(record("job-c"), scene());
    store.create_job(record("job-d"), scene());
    EXPECT_EQ(store.find_job("job-c")->request_id, "");
    EXPECT_EQ(rows("job_requests"), 2);
  }
  // Across a restart, and by the submitter at submission, not the one UpdateJob set since.
  SqliteJobStore store(file());
  JobUpdate moved;
  moved.submitter = "carol";
  store.update_job("job-a", moved);
  const auto found = store.find_job_by_request("alice", "req-1");
  ASSERT_TRUE(found);
  EXPECT_EQ(found->id, "job-a");
  EXPECT_FALSE(store.find_job_by_request("carol", "req-1"));
  EXPECT_EQ(store.find_job_by_request("bob", "req-1")->id, "job-b");
  EXPECT_FALSE(store.find_job_by_request("alice", "req-2"));

  ASSERT_TRUE(store.finish_job("job-a", JobState::kCancelled, "test", 5));
  ASSERT_TRUE(store.delete_job("job-a"));
  EXPECT_FALSE(store.find_job_by_request("alice", "req-1"));
  EXPECT_EQ(rows("job_requests"), 1);
  JobRecord reused = record("job-e");
  reused.submitter = "alice";
  reused.request_id = "req-1";
  EXPECT_EQ(store.create_job(reused, scene()).id, "job-e");
}

// A version 2 file (before request ids) opens as version 3 with its jobs intact, and takes
// request ids from then on.
TEST_F(SqliteJobStoreTest, AVersion2FileIsUpgradedInPlace) {
  {
    SqliteJobStore store(file());
    store.create_job(record("old-job"), scene("old scene"));
  }
  {
    // What version 2 wrote: the same tables without job_requests.
    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open(file().c_str(), &db), SQLITE_OK);
    ASSERT_EQ(sqlite3_exec(db, "DROP TABLE job_requests; PRAGMA user_version = 2;", nullptr,
                           nullptr, nullptr),
              SQLITE_OK);
    sqlite3_close(db);
  }
  SqliteJobStore store(file());
  const auto old = store.find_job("old-job");
  ASSERT_TRUE(old);
  EXPECT_EQ(old->name, "name of old-job");
  EXPECT_EQ(old->request_id, "");
  EXPECT_EQ(store.scene("old-job")->scene_proto, "old scene");
  JobRecord fresh = record("new-job");
  fresh.request_id = "req-1";
  store.create_job(fresh, scene());
  EXPECT_EQ(store.find_job_by_request("", "req-1")->id, "new-job");
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(file().c_str(), &db), SQLITE_OK);
  sqlite3_stmt* q = nullptr;
  sqlite3_prepare_v2(db, "PRAGMA user_version", -1, &q, nullptr);
  sqlite3_step(q);
  EXPECT_EQ(sqlite3_column_int(q, 0), 3);
  sqlite3_finalize(q);
  sqlite3_close(db);
}

}  // namespace
}  // namespace tessera::server
