// test_rpc.cpp — the control-socket protocol without processes: request parsing, every
// method's parameter checks (types, ranges, unknown keys), reply formatting, the status
// object, the program journal, and cutting an interrupted block for resume.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "config/config.hpp"
#include "service/job_journal.hpp"
#include "gcode/move.hpp"
#include "gcode/preprocessor.hpp"
#include "service/resume.hpp"
#include "service/rpc.hpp"
#include "subprocess.hpp"
#include "test_paths.hpp"

namespace pcnc {
namespace {

using rpc::json;

MachineConfig config() { return load_config(test::default_config()); }

// ---- request parsing ----

TEST(RpcParse, ValidRequestKeepsIdMethodParams) {
  auto p = rpc::parse_request(R"({"id":7,"method":"override","params":{"percent":50}})");
  ASSERT_FALSE(p.error) << p.error->message;
  EXPECT_EQ(p.request.id, 7);
  EXPECT_EQ(p.request.method, "override");
  EXPECT_EQ(p.request.params["percent"], 50);

  auto s = rpc::parse_request(R"({"id":"abc","method":"status"})");
  ASSERT_FALSE(s.error);
  EXPECT_EQ(s.request.id, "abc");
  EXPECT_TRUE(s.request.params.is_object());
  EXPECT_TRUE(s.request.params.empty());
}

TEST(RpcParse, InvalidJsonSaysWhere) {
  auto p = rpc::parse_request("{\"id\":1,\"method\":");
  ASSERT_TRUE(p.error);
  EXPECT_EQ(p.error->code, rpc::kParseError);
  EXPECT_NE(p.error->message.find("invalid JSON"), std::string::npos);
  EXPECT_NE(p.error->message.find("column"), std::string::npos) << p.error->message;
  EXPECT_TRUE(p.request.id.is_null());
}

// Issue 19: {"x":1e309} killed the host (an out_of_range escaped parse_request).
TEST(RpcParse, NumbersOutsideDoubleRangeAreAParseErrorNotACrash) {
  for (const char* text : {"{\"id\":7,\"method\":\"status\",\"x\":1e309}", "{\"id\":1e309,\"method\":\"status\"}",
                           "{\"id\":1,\"method\":\"override\",\"params\":{\"percent\":-1e400}}",
                           "{\"id\":1,\"method\":\"jog\",\"params\":{\"axis\":\"x\",\"distance\":[1e999]}}"}) {
    rpc::ParsedRequest p;
    ASSERT_NO_THROW(p = rpc::parse_request(text)) << text;
    ASSERT_TRUE(p.error) << text;
    EXPECT_EQ(p.error->code, rpc::kParseError) << text;
    EXPECT_NE(p.error->message.find("number overflow"), std::string::npos) << p.error->message;
  }
}

TEST(RpcParse, RepeatedMembersAreRefused) {
  auto p = rpc::parse_request("{\"id\":3,\"method\":\"status\",\"method\":\"estop\"}");
  ASSERT_TRUE(p.error);
  EXPECT_EQ(p.error->code, rpc::kInvalidRequest);
  EXPECT_NE(p.error->message.find("'method' appears more than once"), std::string::npos) << p.error->message;
  EXPECT_EQ(p.request.id, 3);
  // inside params too, and the same key in two different objects is fine
  p = rpc::parse_request("{\"id\":4,\"method\":\"override\",\"params\":{\"percent\":50,\"percent\":150}}");
  ASSERT_TRUE(p.error);
  EXPECT_NE(p.error->message.find("'percent'"), std::string::npos) << p.error->message;
  p = rpc::parse_request("{\"id\":5,\"method\":\"set_offset\",\"params\":{\"x\":1,\"y\":{\"x\":2}}}");
  EXPECT_FALSE(p.error && p.error->code == rpc::kInvalidRequest) << p.error->message;
  // a repeated id is not echoed
  p = rpc::parse_request("{\"id\":6,\"id\":7,\"method\":\"status\"}");
  ASSERT_TRUE(p.error);
  EXPECT_TRUE(p.request.id.is_null());
  // an "id" repeated inside params is not the request's: its id is echoed (found by the
  // protocol fuzzer's oracle: the reply carried null)
  p = rpc::parse_request("{\"id\":8,\"method\":\"status\",\"params\":{\"id\":1,\"id\":2}}");
  ASSERT_TRUE(p.error);
  EXPECT_EQ(p.error->code, rpc::kInvalidRequest);
  EXPECT_EQ(p.request.id, 8);
}

TEST(RpcParse, NotARequestObject) {
  for (const char* text : {"[1,2,3]", "42", "\"status\"", "null"}) {
    auto p = rpc::parse_request(text);
    ASSERT_TRUE(p.error) << text;
    EXPECT_EQ(p.error->code, rpc::kInvalidRequest) << text;
  }
}

TEST(RpcParse, MethodMissingOrNotAString) {
  auto a = rpc::parse_request(R"({"id":1})");
  ASSERT_TRUE(a.error);
  EXPECT_EQ(a.error->code, rpc::kInvalidRequest);
  EXPECT_NE(a.error->message.find("missing 'method'"), std::string::npos);
  EXPECT_EQ(a.request.id, 1) << "the id is echoed even when the request is bad";

  auto b = rpc::parse_request(R"({"id":2,"method":5})");
  ASSERT_TRUE(b.error);
  EXPECT_NE(b.error->message.find("'method' must be a string"), std::string::npos);
}

TEST(RpcParse, BadIdParamsAndExtraMembers) {
  auto a = rpc::parse_request(R"({"id":{"x":1},"method":"status"})");
  ASSERT_TRUE(a.error);
  EXPECT_NE(a.error->message.find("'id' must be"), std::string::npos);

  auto b = rpc::parse_request(R"({"id":1,"method":"status","params":[1]})");
  ASSERT_TRUE(b.error);
  EXPECT_EQ(b.error->code, rpc::kInvalidParams);

  auto c = rpc::parse_request(R"({"id":1,"method":"status","parms":{}})");
  ASSERT_TRUE(c.error);
  EXPECT_NE(c.error->message.find("unknown member 'parms'"), std::string::npos);
}

TEST(RpcParse, UnknownMethodListsTheKnownOnes) {
  auto p = rpc::parse_request(R"({"id":1,"method":"fly"})");
  ASSERT_TRUE(p.error);
  EXPECT_EQ(p.error->code, rpc::kMethodNotFound);
  EXPECT_NE(p.error->message.find("'fly'"), std::string::npos);
  for (const auto& m : rpc::method_names()) EXPECT_NE(p.error->message.find(m), std::string::npos) << m;
}

TEST(RpcParse, EveryDocumentedMethodIsKnown) {
  for (const char* m : {"status", "run", "pause", "resume", "stop", "estop", "reset", "override", "jog", "jog_keepalive", "jog_stop",
                        "set_offset", "mdi", "touch_off", "subscribe", "capture", "stream_open", "stream_lines", "stream_close", "probe"}) {
    EXPECT_TRUE(rpc::is_method(m)) << m;
  }
}

// ---- parameters ----

TEST(RpcParams, NoParamsMethodsRefuseParams) {
  EXPECT_FALSE(rpc::check_no_params("pause", json::object()));
  EXPECT_FALSE(rpc::check_no_params("pause", nullptr));
  auto e = rpc::check_no_params("pause", json{{"now", true}});
  ASSERT_TRUE(e);
  EXPECT_NE(e->message.find("unknown parameter 'now' for pause"), std::string::npos);
}

TEST(RpcParams, OverrideRange) {
  EXPECT_EQ(rpc::check_override_params(json{{"percent", 0}}).value->percent, 0.0);
  EXPECT_EQ(rpc::check_override_params(json{{"percent", 200}}).value->percent, 200.0);
  EXPECT_EQ(rpc::check_override_params(json{{"percent", 87.5}}).value->percent, 87.5);
  for (const json& bad : {json{{"percent", 200.5}}, json{{"percent", -1}}, json{{"percent", "50"}}, json::object(),
                          json{{"percent", nullptr}}}) {
    auto r = rpc::check_override_params(bad);
    EXPECT_FALSE(r.ok()) << bad.dump();
    EXPECT_EQ(r.error.code, rpc::kInvalidParams);
  }
  EXPECT_NE(rpc::check_override_params(json{{"percent", 250}}).error.message.find("out of range"), std::string::npos);
  EXPECT_NE(rpc::check_override_params(json{{"percent", "x"}}).error.message.find("must be a number"), std::string::npos);
  EXPECT_NE(rpc::check_override_params(json::object()).error.message.find("missing parameter 'percent'"), std::string::npos);
}

TEST(RpcParams, JogIncrementalAndContinuous) {
  const MachineConfig c = config();
  auto a = rpc::check_jog_params(json{{"axis", "x"}, {"distance", -1.5}, {"feed", 300}}, c);
  ASSERT_TRUE(a.ok()) << a.error.message;
  EXPECT_EQ(a.value->axis, 0);
  EXPECT_FALSE(a.value->continuous);
  EXPECT_EQ(a.value->distance_mm, -1.5);
  EXPECT_EQ(a.value->feed_mm_min, 300.0);

  auto b = rpc::check_jog_params(json{{"axis", "Z"}, {"continuous", true}, {"direction", "-"}}, c);
  ASSERT_TRUE(b.ok()) << b.error.message;
  EXPECT_EQ(b.value->axis, 2);
  EXPECT_TRUE(b.value->continuous);
  EXPECT_EQ(b.value->direction, -1);
  EXPECT_GT(b.value->feed_mm_min, 0.0) << "a default feed";
  EXPECT_LE(b.value->feed_mm_min, c.axes[2].max_velocity_mm_s * 60.0);

  auto d = rpc::check_jog_params(json{{"axis", "Y"}, {"continuous", true}, {"direction", 1}}, c);
  ASSERT_TRUE(d.ok());
  EXPECT_EQ(d.value->direction, 1);
}

TEST(RpcParams, JogRefusals) {
  const MachineConfig c = config();
  const double x_max_mm_min = c.axes[0].max_velocity_mm_s * 60.0;
  struct Case {
    json params;
    const char* says;
  };
  const Case cases[] = {
      {json{{"axis", "Q"}, {"distance", 1}}, "must be X, Y or Z"},
      {json{{"axis", 0}, {"distance", 1}}, "must be a string"},
      {json{{"distance", 1}}, "missing parameter 'axis'"},
      {json{{"axis", "X"}}, "missing parameter 'distance'"},
      {json{{"axis", "X"}, {"distance", 0}}, "must not be 0"},
      {json{{"axis", "X"}, {"distance", "1"}}, "must be a number"},
      {json{{"axis", "X"}, {"distance", 5000}}, "out of range"},
      {json{{"axis", "X"}, {"distance", 1}, {"feed", x_max_mm_min + 1}}, "out of range"},
      {json{{"axis", "X"}, {"distance", 1}, {"feed", 0}}, "must be > 0"},
      {json{{"axis", "X"}, {"distance", 1}, {"feed", -5}}, "out of range"},
      {json{{"axis", "X"}, {"distance", 1}, {"direction", "+"}}, "takes 'distance', not 'direction'"},
      {json{{"axis", "X"}, {"continuous", true}}, "missing parameter 'direction'"},
      {json{{"axis", "X"}, {"continuous", true}, {"direction", "up"}}, "must be \"+\", \"-\", 1 or -1"},
      {json{{"axis", "X"}, {"continuous", true}, {"direction", 2}}, "must be \"+\", \"-\", 1 or -1"},
      {json{{"axis", "X"}, {"continuous", true}, {"direction", "+"}, {"distance", 1}}, "takes 'direction', not 'distance'"},
      {json{{"axis", "X"}, {"continuous", "yes"}, {"direction", "+"}}, "must be true or false"},
      {json{{"axis", "X"}, {"distance", 1}, {"speed", 3}}, "unknown parameter 'speed'"},
  };
  for (const auto& k : cases) {
    auto r = rpc::check_jog_params(k.params, c);
    ASSERT_FALSE(r.ok()) << k.params.dump();
    EXPECT_EQ(r.error.code, rpc::kInvalidParams);
    EXPECT_NE(r.error.message.find(k.says), std::string::npos) << k.params.dump() << " -> " << r.error.message;
  }
}

TEST(RpcParams, JogFeedLimitIsPerAxis) {
  const MachineConfig c = config();
  const double z_max = c.axes[2].max_velocity_mm_s * 60.0;
  const double x_max = c.axes[0].max_velocity_mm_s * 60.0;
  ASSERT_LT(z_max, x_max) << "the default machine's Z is slower than X";
  EXPECT_TRUE(rpc::check_jog_params(json{{"axis", "X"}, {"distance", 1}, {"feed", x_max}}, c).ok());
  EXPECT_FALSE(rpc::check_jog_params(json{{"axis", "Z"}, {"distance", 1}, {"feed", x_max}}, c).ok());
  EXPECT_TRUE(rpc::check_jog_params(json{{"axis", "Z"}, {"distance", 1}, {"feed", z_max}}, c).ok());
}

TEST(RpcParams, RunSetOffsetSubscribe) {
  auto r = rpc::check_run_params(json{{"file", "/a.ngc"}, {"work_offset", "g59"}, {"contouring", true}, {"fit", true}});
  ASSERT_TRUE(r.ok()) << r.error.message;
  EXPECT_EQ(r.value->work_offset, 5);
  EXPECT_EQ(r.value->contouring, true);
  EXPECT_TRUE(r.value->fit);
  EXPECT_FALSE(rpc::check_run_params(json::object()).ok());
  EXPECT_FALSE(rpc::check_run_params(json{{"file", ""}}).ok());
  EXPECT_FALSE(rpc::check_run_params(json{{"file", "/a"}, {"work_offset", "G60"}}).ok());
  EXPECT_FALSE(rpc::check_run_params(json{{"file", "/a"}, {"contouring", "on"}}).ok());
  // offset: `pcnc ctl run --offset X,Y,Z`, G54 for this run
  auto off = rpc::check_run_params(json{{"file", "/a"}, {"offset", {{"x", 1.5}, {"y", -2}, {"z", 25}}}});
  ASSERT_TRUE(off.ok()) << off.error.message;
  ASSERT_TRUE(off.value->offset.has_value());
  EXPECT_EQ((*off.value->offset)[0], 1.5);
  EXPECT_EQ((*off.value->offset)[1], -2.0);
  EXPECT_EQ((*off.value->offset)[2], 25.0);
  EXPECT_FALSE(r.value->offset.has_value()) << "no offset given: the work offset's G54";
  EXPECT_FALSE(rpc::check_run_params(json{{"file", "/a"}, {"offset", "1,2,3"}}).ok());
  EXPECT_FALSE(rpc::check_run_params(json{{"file", "/a"}, {"offset", {{"x", 1}, {"y", 2}}}}).ok()) << "all three axes";
  EXPECT_FALSE(rpc::check_run_params(json{{"file", "/a"}, {"offset", {{"x", 1}, {"y", 2}, {"z", 2e5}}}}).ok());
  EXPECT_FALSE(rpc::check_run_params(json{{"file", "/a"}, {"offset", {{"x", 1}, {"y", 2}, {"z", 3}, {"w", 4}}}}).ok());

  auto o = rpc::check_set_offset_params(json{{"offset", "G55"}, {"x", 5}, {"z", -2.5}});
  ASSERT_TRUE(o.ok()) << o.error.message;
  EXPECT_EQ(o.value->index, 1);
  EXPECT_EQ(o.value->xyz[0], 5.0);
  EXPECT_FALSE(o.value->xyz[1].has_value()) << "a missing axis stays unchanged";
  EXPECT_EQ(o.value->xyz[2], -2.5);
  EXPECT_FALSE(rpc::check_set_offset_params(json{{"offset", "G55"}}).ok()) << "needs an axis";
  EXPECT_FALSE(rpc::check_set_offset_params(json{{"offset", "G53"}, {"x", 1}}).ok());
  EXPECT_FALSE(rpc::check_set_offset_params(json{{"offset", "G54"}, {"x", "1"}}).ok());
  EXPECT_EQ(rpc::check_set_offset_params(json{{"offset", "G59.1"}, {"x", 1}}).value->index, 6);
  EXPECT_EQ(rpc::check_set_offset_params(json{{"offset", "g59.3"}, {"x", 1}}).value->index, 8);
  const auto bad = rpc::check_set_offset_params(json{{"offset", "G59.4"}, {"x", 1}});
  EXPECT_FALSE(bad.ok());
  EXPECT_NE(bad.error.message.find("G54..G59, G59.1, G59.2, G59.3"), std::string::npos) << bad.error.message;
  // A program starts in G54..G59 (the interpreter selects among those).
  EXPECT_FALSE(rpc::check_run_params(json{{"file", "/a"}, {"work_offset", "G59.1"}}).ok());

  EXPECT_EQ(rpc::check_subscribe_params(json::object()).value->rate_hz, 10.0);
  EXPECT_EQ(rpc::check_subscribe_params(json{{"rate_hz", 50}}).value->rate_hz, 50.0);
  EXPECT_EQ(rpc::check_subscribe_params(json{{"rate_hz", 0}}).value->rate_hz, 0.0);
  EXPECT_FALSE(rpc::check_subscribe_params(json{{"rate_hz", 50.5}}).ok()) << "at most 50 Hz";
  EXPECT_FALSE(rpc::check_subscribe_params(json{{"rate_hz", -1}}).ok());
}

TEST(RpcParams, NamesOfAxesAndOffsets) {
  EXPECT_EQ(rpc::parse_axis_name("y"), 1);
  EXPECT_EQ(rpc::parse_axis_name("A"), -1);
  EXPECT_EQ(rpc::parse_work_offset_name("G57"), 3);
  EXPECT_EQ(rpc::parse_work_offset_name("G5"), -1);
  EXPECT_EQ(rpc::work_offset_name(0), "G54");
  EXPECT_EQ(rpc::work_offset_name(5), "G59");
  EXPECT_EQ(rpc::work_offset_name(6), "G59.1");
  EXPECT_EQ(rpc::work_offset_name(8), "G59.3");
  EXPECT_EQ(rpc::parse_work_offset_name("G59.2"), 7);
}

// ---- replies ----

TEST(RpcReply, OneLineEachWithTheId) {
  const std::string ok = rpc::format_result(3, json{{"a", 1}});
  ASSERT_EQ(ok.back(), '\n');
  EXPECT_EQ(ok.find('\n'), ok.size() - 1) << "exactly one line";
  const json j = json::parse(ok);
  EXPECT_EQ(j["id"], 3);
  EXPECT_EQ(j["result"]["a"], 1);

  const std::string err = rpc::format_error("x", rpc::Error{rpc::kRefused, "no", json{{"k", 2}}});
  const json e = json::parse(err);
  EXPECT_EQ(e["id"], "x");
  EXPECT_EQ(e["error"]["code"], rpc::kRefused);
  EXPECT_EQ(e["error"]["message"], "no");
  EXPECT_EQ(e["error"]["data"]["k"], 2);

  const json n = json::parse(rpc::format_notification("status", json{{"s", 1}}));
  EXPECT_FALSE(n.contains("id"));
  EXPECT_EQ(n["method"], "status");
}

TEST(RpcReply, InvalidUtf8IsReplacedNotThrown) {
  const std::string bad = std::string("bad \xff\xfe byte");
  std::string line;
  ASSERT_NO_THROW(line = rpc::format_error(nullptr, rpc::Error{rpc::kParseError, bad, nullptr}));
  json parsed;
  EXPECT_NO_THROW(parsed = json::parse(line));
  EXPECT_EQ(parsed["error"]["code"], rpc::kParseError);
}

TEST(RpcReply, StatusObject) {
  Status s;
  s.state = MachineState::kRunning;
  s.line = 12;
  s.commanded = {1.0, 2.0, 3.0};
  s.actual = {1.1, 2.2, 3.3};
  s.following_error = {-0.1, -0.2, -0.3};
  s.feed_override = 1.25;
  s.ring_fill = 3;
  s.underruns = 4;
  s.timing.compute_p99_us = 7.5;
  s.fault = FaultCode::kFollowingError;
  s.fault_axis = 1;
  s.program_cycles = 4;
  s.following_error_sq_sum = {4.0 * 0.01, 0.0, 0.0};
  s.max_contour_error = 0.02;
  const json j = rpc::status_to_json(s);
  EXPECT_NEAR(j["rms_following_error"]["x"].get<double>(), 0.1, 1e-12);
  EXPECT_EQ(j["max_contour_error"], 0.02);
  EXPECT_EQ(j["state"], "RUNNING");
  EXPECT_EQ(j["line"], 12);
  EXPECT_EQ(j["commanded"]["z"], 3.0);
  EXPECT_EQ(j["actual"]["y"], 2.2);
  EXPECT_EQ(j["following_error"]["x"], -0.1);
  EXPECT_EQ(j["feed_override_percent"], 125.0);
  EXPECT_EQ(j["ring_fill"], 3);
  EXPECT_EQ(j["underruns"], 4);
  EXPECT_EQ(j["timing"]["compute_p99_us"], 7.5);
  EXPECT_EQ(j["fault"], "following error");
  EXPECT_EQ(j["fault_axis"], "Y");
}

// ---- journal ----

TEST(JobJournal, RoundTripAndMissingFile) {
  const std::string dir = test::make_temp_dir("journal");
  const std::string path = journal_path(dir);  // the journal in the state directory
  JobJournal j;
  j.file = "/some/prog.ngc";
  j.work_offset = 2;
  j.work_offsets[2] = {1.5, 2.5, 3.5};
  j.fit = true;
  j.contouring = 1;
  j.start_position = {12.5, 12.5, 25.0};
  j.file_size = 1234;
  j.file_mtime_ns = 987654321012345;
  j.host_pid = 42;
  j.seq_base = 17;
  std::string err;
  ASSERT_TRUE(write_journal(path, j, &err)) << err;
  auto r = read_journal(path, &err);
  ASSERT_TRUE(r) << err;
  EXPECT_EQ(r->file, j.file);
  EXPECT_EQ(r->work_offset, 2);
  EXPECT_EQ(r->work_offsets[2], j.work_offsets[2]);
  EXPECT_TRUE(r->fit);
  EXPECT_EQ(r->contouring, 1);
  EXPECT_EQ(r->start_position, j.start_position);
  EXPECT_EQ(r->file_size, 1234u);
  EXPECT_EQ(r->file_mtime_ns, j.file_mtime_ns);
  EXPECT_EQ(r->seq_base, 17u);
  remove_journal(path);
  EXPECT_FALSE(read_journal(path, &err));
  EXPECT_NE(err.find("no program journal"), std::string::npos);
}

TEST(JobJournal, CarriesG59_3AndReadsAnOlderJournalWithSix) {
  const std::string dir = test::make_temp_dir("journal9");
  const std::string path = journal_path(dir);
  JobJournal j;
  j.file = "/p.ngc";
  for (std::size_t i = 0; i < j.work_offsets.size(); ++i) j.work_offsets[i] = {1.0 * i, 2.0, -3.0};
  std::string err;
  ASSERT_TRUE(write_journal(path, j, &err)) << err;
  auto r = read_journal(path, &err);
  ASSERT_TRUE(r) << err;
  EXPECT_EQ(r->work_offsets, j.work_offsets);

  // An older pcnc-host wrote G54..G59 only: still read, G59.1..G59.3 zero.
  nlohmann::json doc = nlohmann::json::parse(test::read_file(path));
  while (doc["work_offsets"].size() > 6) doc["work_offsets"].erase(6);
  ASSERT_EQ(doc["work_offsets"].size(), 6u);
  ASSERT_TRUE(write_file_atomically(path, doc.dump(), &err)) << err;
  r = read_journal(path, &err);
  ASSERT_TRUE(r) << err;
  EXPECT_EQ(r->work_offsets[5], j.work_offsets[5]);
  EXPECT_EQ(r->work_offsets[6], (Vec3{0, 0, 0}));
}

// ---- resume: cutting the interrupted block ----

Block line_block(const MachineConfig& c, Vec3 a, Vec3 b, double feed) {
  Move m;
  m.kind = MoveKind::kLine;
  m.line = 9;
  m.start = a;
  m.end = b;
  m.feed_mm_s = feed;
  m.contouring = true;
  return make_block(m, c);
}

TEST(Resume, LineContinuesFromThePointToTheSameEnd) {
  const MachineConfig c = config();
  const Block b = line_block(c, {2, 2, 20}, {12, 2, 20}, 10.0);
  std::string why;
  auto k = continue_block(b, {5.5, 2, 20}, c, 0.005, &why);
  ASSERT_TRUE(k) << why;
  ASSERT_FALSE(k->skip);
  EXPECT_EQ(k->block.kind, BlockKind::kLine);
  EXPECT_EQ(k->block.line, 9u);
  EXPECT_EQ(k->block.start, (Vec3{5.5, 2, 20}));
  EXPECT_EQ(k->block.end, b.end);
  EXPECT_NEAR(k->block.length, 6.5, 1e-12);
  EXPECT_NEAR(k->block.speed, b.speed, 1e-12) << "same feed limit";
  EXPECT_EQ(k->block.contouring, 1);
}

TEST(Resume, PointOffTheLineIsRefusedAndTheEndIsSkipped) {
  const MachineConfig c = config();
  const Block b = line_block(c, {2, 2, 20}, {12, 2, 20}, 10.0);
  std::string why;
  EXPECT_FALSE(continue_block(b, {5.5, 2.5, 20}, c, 0.005, &why));
  EXPECT_NE(why.find("not on"), std::string::npos) << why;
  EXPECT_FALSE(continue_block(b, {13, 2, 20}, c, 0.005, &why)) << "beyond the end";
  auto at_end = continue_block(b, {12, 2, 20}, c, 0.005, &why);
  ASSERT_TRUE(at_end);
  EXPECT_TRUE(at_end->skip);
}

TEST(Resume, ArcContinuesWithTheRemainingSweep) {
  const MachineConfig c = config();
  Move m;
  m.kind = MoveKind::kArc;
  m.start = {18.5, 12.5, 20};
  m.end = {6.5, 12.5, 20};
  m.center = {12.5, 12.5, 20};
  m.radius = 6.0;
  m.sweep = std::numbers::pi;  // counter-clockwise half circle through the top
  m.feed_mm_s = 10.0;
  const Block b = make_block(m, c);
  // A quarter of the way round from angle 0 the machine stands at 45 degrees.
  const double a = std::numbers::pi / 4.0;
  const Vec3 at{12.5 + 6.0 * std::cos(a), 12.5 + 6.0 * std::sin(a), 20};
  std::string why;
  auto k = continue_block(b, at, c, 0.005, &why);
  ASSERT_TRUE(k) << why;
  ASSERT_FALSE(k->skip);
  EXPECT_EQ(k->block.kind, BlockKind::kArc);
  EXPECT_NEAR(k->block.arc.sweep, 0.75 * std::numbers::pi, 1e-9);
  EXPECT_NEAR(k->block.arc.start_angle, a, 1e-9);
  EXPECT_NEAR(k->block.length, 6.0 * 0.75 * std::numbers::pi, 1e-9);
  EXPECT_EQ(k->block.end, b.end);
  // A point inside the circle is not on the path.
  EXPECT_FALSE(continue_block(b, {12.5, 15.0, 20}, c, 0.005, &why));
}

TEST(Resume, PauseIsSkippedDwellRepeatedEmptyNurbsRefused) {
  const MachineConfig c = config();
  Block p;
  p.kind = BlockKind::kPause;
  std::string why;
  auto kp = continue_block(p, {1, 1, 1}, c, 0.005, &why);
  ASSERT_TRUE(kp);
  EXPECT_TRUE(kp->skip);
  Block d;
  d.kind = BlockKind::kDwell;
  d.dwell_s = 2.0;
  auto kd = continue_block(d, {1, 1, 1}, c, 0.005, &why);
  ASSERT_TRUE(kd);
  EXPECT_FALSE(kd->skip);
  EXPECT_EQ(kd->block.dwell_s, 2.0);
  Block n;  // a NURBS block with no curve (valid ones are cut: tests/test_resume.cpp)
  n.kind = BlockKind::kNurbs;
  EXPECT_FALSE(continue_block(n, {1, 1, 1}, c, 0.005, &why));
  EXPECT_NE(why.find("NURBS block is invalid"), std::string::npos) << why;
}

TEST(RpcParams, Mdi) {
  auto m = rpc::check_mdi_params(json{{"text", "G1 X5 F300\nG0 Z1"}});
  ASSERT_TRUE(m.ok()) << m.error.message;
  EXPECT_EQ(m.value->text, "G1 X5 F300\nG0 Z1");
  EXPECT_FALSE(rpc::check_mdi_params(json::object()).ok()) << "text is required";
  EXPECT_FALSE(rpc::check_mdi_params(json{{"text", 5}}).ok());
  EXPECT_FALSE(rpc::check_mdi_params(json{{"text", ""}}).ok());
  EXPECT_FALSE(rpc::check_mdi_params(json{{"text", " \n\t"}}).ok()) << "no line of G-code";
  EXPECT_FALSE(rpc::check_mdi_params(json{{"text", std::string(rpc::kMaxMdiBytes + 1, 'G')}}).ok());
  EXPECT_FALSE(rpc::check_mdi_params(json{{"text", std::string("G0\0X1", 6)}}).ok());
  const auto unknown = rpc::check_mdi_params(json{{"text", "G0 X1"}, {"file", "x"}});
  ASSERT_FALSE(unknown.ok());
  EXPECT_EQ(unknown.error.code, rpc::kInvalidParams);
  EXPECT_NE(unknown.error.message.find("unknown parameter 'file'"), std::string::npos) << unknown.error.message;
  // a repeated key is refused when the request is parsed, before the parameters are checked
  EXPECT_TRUE(rpc::parse_request(R"({"id":1,"method":"mdi","params":{"text":"G0 X1","text":"G0 X9"}})").error);
}

TEST(RpcParams, TouchOff) {
  auto t = rpc::check_touch_off_params(json{{"axis", "z"}, {"value", -1.25}});
  ASSERT_TRUE(t.ok()) << t.error.message;
  EXPECT_EQ(t.value->axis, 2);
  EXPECT_DOUBLE_EQ(t.value->value, -1.25);
  EXPECT_FALSE(rpc::check_touch_off_params(json{{"axis", "X"}}).ok()) << "value is required";
  EXPECT_FALSE(rpc::check_touch_off_params(json{{"value", 0}}).ok()) << "axis is required";
  EXPECT_FALSE(rpc::check_touch_off_params(json{{"axis", "A"}, {"value", 0}}).ok());
  EXPECT_FALSE(rpc::check_touch_off_params(json{{"axis", 0}, {"value", 0}}).ok());
  EXPECT_FALSE(rpc::check_touch_off_params(json{{"axis", "X"}, {"value", "0"}}).ok());
  EXPECT_FALSE(rpc::check_touch_off_params(json{{"axis", "X"}, {"value", 1e5}}).ok()) << "within ±1e4 mm like set_offset";
  EXPECT_FALSE(rpc::check_touch_off_params(json{{"axis", "X"}, {"value", 0}, {"offset", "G55"}}).ok()) << "the active system only";
}

}  // namespace
}  // namespace pcnc
