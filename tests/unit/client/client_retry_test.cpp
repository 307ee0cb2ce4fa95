// tessera::Client's submit retries, against a scripted RenderService in this process: a
// request with a request id is sent again, with the same id, after DEADLINE_EXCEEDED or
// UNAVAILABLE, a bounded number of times; without an id, or on any other error, once.
#include <grpcpp/grpcpp.h>
#include <gtest/gtest.h>

#include <mutex>
#include <set>
#include <vector>

#include "client/client.hpp"

namespace tessera {
namespace {

using namespace std::chrono_literals;

// Answers SubmitJob with the scripted codes in turn, then OK with a job.
class ScriptedService final : public v1::RenderService::Service {
 public:
  explicit ScriptedService(std::vector<grpc::StatusCode> failures)
      : failures_(std::move(failures)) {}

  grpc::Status SubmitJob(grpc::ServerContext*, const v1::SubmitJobRequest* request,
                         v1::SubmitJobResponse* response) override {
    std::lock_guard lock(mutex_);
    request_ids_.push_back(request->request_id());
    if (calls_ < failures_.size()) return grpc::Status(failures_[calls_++], "scripted failure");
    ++calls_;
    response->mutable_job()->set_id("job-1");
    response->mutable_job()->set_request_id(request->request_id());
    return grpc::Status::OK;
  }

  std::vector<std::string> request_ids() {
    std::lock_guard lock(mutex_);
    return request_ids_;
  }

 private:
  std::mutex mutex_;
  std::vector<grpc::StatusCode> failures_;
  std::size_t calls_ = 0;
  std::vector<std::string> request_ids_;
};

class ClientRetryTest : public ::testing::Test {
 protected:
  void serve(std::vector<grpc::StatusCode> failures) {
    service_ = std::make_unique<ScriptedService>(std::move(failures));
    grpc::ServerBuilder builder;
    int port = 0;
    builder.AddListeningPort("127.0.0.1:0", grpc::InsecureServerCredentials(), &port);
    builder.RegisterService(service_.get());
    server_ = builder.BuildAndStart();
    ASSERT_TRUE(server_);
    address_ = "127.0.0.1:" + std::to_string(port);
  }
  void TearDown() override {
    if (server_) server_->Shutdown();
  }

  Client client(int attempts) const {
    return Client(
        ClientOptions{.target = address_, .submit_attempts = attempts, .submit_retry_pause = 10ms});
  }

  std::unique_ptr<ScriptedService> service_;
  std::unique_ptr<grpc::Server> server_;
  std::string address_;
};

v1::SubmitJobRequest request_with_id(const std::string& id) {
  v1::SubmitJobRequest request;
  request.set_name("retried");
  request.set_request_id(id);
  return request;
}

TEST_F(ClientRetryTest, ARequestWithAnIdIsRetriedWithTheSameIdUntilItGetsThrough) {
  serve({grpc::StatusCode::DEADLINE_EXCEEDED, grpc::StatusCode::UNAVAILABLE});
  const v1::Job job = client(4).submit(request_with_id("abc123"));
  EXPECT_EQ(job.id(), "job-1");
  EXPECT_EQ(service_->request_ids(), (std::vector<std::string>{"abc123", "abc123", "abc123"}));
}

TEST_F(ClientRetryTest, RetriesAreBoundedAndEndWithTheLastError) {
  serve({grpc::StatusCode::UNAVAILABLE, grpc::StatusCode::UNAVAILABLE,
         grpc::StatusCode::DEADLINE_EXCEEDED, grpc::StatusCode::UNAVAILABLE});
  try {
    client(3).submit(request_with_id("abc123"));
    FAIL() << "the submission succeeded";
  } catch (const ClientError& e) {
    EXPECT_EQ(e.code(), grpc::StatusCode::DEADLINE_EXCEEDED) << e.what();
  }
  EXPECT_EQ(service_->request_ids().size(), 3u);
}

TEST_F(ClientRetryTest, WithoutAnIdOrOnOtherErrorsThereIsOneAttempt) {
  serve({grpc::StatusCode::UNAVAILABLE, grpc::StatusCode::ALREADY_EXISTS});
  try {
    client(4).submit(request_with_id(""));  // a retry could create a second job
    FAIL() << "the submission succeeded";
  } catch (const ClientError& e) {
    EXPECT_EQ(e.code(), grpc::StatusCode::UNAVAILABLE);
  }
  EXPECT_EQ(service_->request_ids().size(), 1u);
  try {
    client(4).submit(request_with_id("reused"));  // ALREADY_EXISTS: a new id is needed
    FAIL() << "the submission succeeded";
  } catch (const ClientError& e) {
    EXPECT_EQ(e.code(), grpc::StatusCode::ALREADY_EXISTS);
  }
  EXPECT_EQ(service_->request_ids().size(), 2u);
}

TEST(RequestIds, AreThirtyTwoHexDigitsAndDoNotRepeat) {
  std::set<std::string> seen;
  for (int i = 0; i < 1000; ++i) {
    const std::string id = make_request_id();
    ASSERT_EQ(id.size(), 32u);
    EXPECT_EQ(id.find_first_not_of("0123456789abcdef"), std::string::npos) << id;
    seen.insert(id);
  }
  EXPECT_EQ(seen.size(), 1000u);
}

}  // namespace
}  // namespace tessera
