#include "core/config.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "sim/env_config.h"
#include "tests/common/test_support.h"

namespace flsd {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;
using testutil::InputErrorMessage;
using testutil::TempFile;

// A config with one field of every kind the reader supports, including a nested section.
struct InnerConfig {
  double gain = 0.5;
  Interval span{0.0, 1.0};
  template <class V>
  void Visit(V& v) {
    v("gain", gain);
    v("span", span, Bounds<double>{-1.0, 2.0});
  }
};

struct SampleConfig {
  int count = 3;
  double rate = 0.25;
  bool verbose = false;
  std::string name = "default";
  Interval window{0.5, 1.5};
  InnerConfig inner;
  template <class V>
  void Visit(V& v) {
    v("count", count, Bounds<int>{1, 10});
    v("rate", rate);
    v("verbose", verbose);
    v("name", name);
    v("window", window);
    v("inner", inner);
  }
};

constexpr const char* kWhere = "sample.yaml: sample";

SampleConfig Read(const std::string& yaml) {
  SampleConfig config;
  ReadConfig(YAML::Load(yaml), kWhere, config);
  return config;
}

std::string ReadError(const std::string& yaml) {
  return InputErrorMessage([&] { Read(yaml); });
}

void ExpectSameConfig(const SampleConfig& a, const SampleConfig& b) {
  EXPECT_EQ(a.count, b.count);
  EXPECT_EQ(a.rate, b.rate);  // exact: doubles must survive the text round trip bit for bit
  EXPECT_EQ(a.verbose, b.verbose);
  EXPECT_EQ(a.name, b.name);
  EXPECT_EQ(a.window, b.window);
  EXPECT_EQ(a.inner.gain, b.inner.gain);
  EXPECT_EQ(a.inner.span, b.inner.span);
}

TEST(ConfigReader, ReadsEveryKindOfField) {
  const SampleConfig c = Read(
      "count: 7\nrate: -2.5\nverbose: true\nname: trot fast\nwindow: [-1, 4.5]\n"
      "inner: {gain: 3.25, span: [0.25, 1.75]}\n");
  EXPECT_EQ(c.count, 7);
  EXPECT_EQ(c.rate, -2.5);
  EXPECT_TRUE(c.verbose);
  EXPECT_EQ(c.name, "trot fast");
  EXPECT_EQ(c.window, (Interval{-1.0, 4.5}));
  EXPECT_EQ(c.inner.gain, 3.25);
  EXPECT_EQ(c.inner.span, (Interval{0.25, 1.75}));
}

TEST(ConfigReader, MissingKeysKeepTheirDefaults) {
  const SampleConfig defaults;
  const SampleConfig c = Read("count: 9\ninner: {gain: 2.0}\n");
  EXPECT_EQ(c.count, 9);
  EXPECT_EQ(c.inner.gain, 2.0);
  SampleConfig expected = defaults;
  expected.count = 9;
  expected.inner.gain = 2.0;
  ExpectSameConfig(c, expected);
  // An empty document and an empty (null) section change nothing.
  ExpectSameConfig(Read(""), defaults);
  ExpectSameConfig(Read("inner:\n"), defaults);
}

TEST(ConfigReader, UnknownKeyIsNamedWithItsPathAndTheKnownKeys) {
  EXPECT_THAT(ReadError("count: 2\ncuont: 3\n"),
              AllOf(HasSubstr("sample.yaml: sample.cuont"), HasSubstr("unknown key"),
                    HasSubstr("count, inner, name, rate, verbose, window")));
  EXPECT_THAT(ReadError("inner: {gian: 1.0}\n"),
              AllOf(HasSubstr("sample.yaml: sample.inner.gian"), HasSubstr("gain, span")));
}

TEST(ConfigReader, OutOfBoundsValueNamesKeyBoundsAndValue) {
  EXPECT_THAT(ReadError("count: 11\n"),
              AllOf(HasSubstr("sample.count"), HasSubstr("[1, 10]"), HasSubstr("got 11")));
  EXPECT_THAT(ReadError("count: 0\n"), AllOf(HasSubstr("sample.count"), HasSubstr("got 0")));
  // Both ends of a bounded interval are checked.
  EXPECT_THAT(
      ReadError("inner: {span: [-2, 1]}\n"),
      AllOf(HasSubstr("sample.inner.span"), HasSubstr("[-1, 2]"), HasSubstr("got [-2, 1]")));
  EXPECT_THAT(ReadError("inner: {span: [0, 2.5]}\n"), HasSubstr("got [0, 2.5]"));
  // The bounds themselves are inclusive.
  EXPECT_EQ(Read("count: 10\n").count, 10);
  EXPECT_EQ(Read("inner: {span: [-1, 2]}\n").inner.span, (Interval{-1.0, 2.0}));
}

TEST(ConfigReader, WrongTypeNamesKeyAndExpectedKind) {
  EXPECT_THAT(ReadError("count: abc\n"),
              AllOf(HasSubstr("sample.count"), HasSubstr("an integer"), HasSubstr("'abc'")));
  EXPECT_THAT(ReadError("count: 2.5\n"), HasSubstr("an integer"));
  EXPECT_THAT(ReadError("count: 99999999999\n"), HasSubstr("an integer"));  // overflows int
  EXPECT_THAT(ReadError("rate: fast\n"), AllOf(HasSubstr("sample.rate"), HasSubstr("a number")));
  EXPECT_THAT(ReadError("verbose: maybe\n"),
              AllOf(HasSubstr("sample.verbose"), HasSubstr("true or false")));
  EXPECT_THAT(ReadError("count: [1, 2]\n"), HasSubstr("a single value"));
  EXPECT_THAT(ReadError("inner: 3\n"), AllOf(HasSubstr("sample.inner"), HasSubstr("a mapping")));
  EXPECT_THAT(ReadError("window: [1]\n"),
              AllOf(HasSubstr("sample.window"), HasSubstr("a range [lo, hi]")));
  EXPECT_THAT(ReadError("window: [a, b]\n"), HasSubstr("of numbers"));
}

TEST(ConfigReader, IntervalWithLoAboveHiIsRejected) {
  EXPECT_THAT(ReadError("window: [2, 1]\n"),
              AllOf(HasSubstr("sample.window"), HasSubstr("lo <= hi"), HasSubstr("[2, 1]")));
  EXPECT_THAT(ReadError("window: [.nan, 1]\n"), HasSubstr("lo <= hi"));
  EXPECT_EQ(Read("window: [2, 2]\n").window, (Interval{2.0, 2.0}));  // a point is allowed
}

TEST(ConfigReader, SectionThatIsNotAMappingIsRejected) {
  SampleConfig config;
  EXPECT_THAT(InputErrorMessage([&] { ReadConfig(YAML::Load("[1, 2]"), kWhere, config); }),
              AllOf(HasSubstr(kWhere), HasSubstr("a mapping")));
}

TEST(ConfigWriter, ToYamlThenReadConfigGivesEqualValues) {
  SampleConfig original;
  original.count = 8;
  original.rate = 0.1;  // not exact in binary: needs all 17 digits to come back equal
  original.verbose = true;
  original.name = "a: tricky # string";
  original.window = {-1.0 / 3.0, 2.0 / 3.0};
  original.inner.gain = 1e-300;
  original.inner.span = {-0.75, 1.9};

  const std::string text = ToYamlString(original);
  SampleConfig back;  // starts from defaults, all of which differ from `original`
  ReadConfig(YAML::Load(text), "round trip", back);
  ExpectSameConfig(back, original);
}

TEST(LoadYamlFile, MissingFileIsNamed) {
  const std::string path = "/nonexistent/flsd/missing.yaml";
  EXPECT_THAT(InputErrorMessage([&] { LoadYamlFile(path); }),
              AllOf(HasSubstr(path), HasSubstr("cannot open")));
}

TEST(LoadYamlFile, MalformedFileIsNamedWithTheLine) {
  const TempFile file(".yaml", "a: 1\nb: 2\nc: d: e\n");  // the third line is not YAML
  EXPECT_THAT(InputErrorMessage([&] { LoadYamlFile(file.path()); }),
              AllOf(HasSubstr(file.path() + ":3:"), HasSubstr("malformed YAML")));
}

// A file's name relative to another's folder: `base:` paths are relative to the including file.
std::string BaseName(const TempFile& file) { return std::filesystem::path(file.path()).filename().string(); }

TEST(LoadConfigFile, ABaseIsMergedUnderTheFileKeyByKey) {
  const TempFile base(".yaml", "count: 4\nname: base\ninner:\n  gain: 0.1\n  span: [0, 2]\n");
  const TempFile file(".yaml", "base: " + BaseName(base) + "\nname: child\ninner:\n  span: [-1, 1]\n");
  SampleConfig config;
  ReadConfig(LoadConfigFile(file.path()), file.path() + ":", config);
  EXPECT_EQ(config.count, 4);           // from the base
  EXPECT_EQ(config.name, "child");      // replaced
  EXPECT_DOUBLE_EQ(config.inner.gain, 0.1);  // a section merges key by key
  EXPECT_EQ(config.inner.span, (Interval{-1.0, 1.0}));  // a list is replaced whole
}

TEST(LoadConfigFile, BasesChainAndTheBaseFileIsUnchanged) {
  const TempFile root(".yaml", "count: 2\nrate: 0.5\n");
  const TempFile middle(".yaml", "base: " + BaseName(root) + "\nrate: 0.75\n");
  const TempFile top(".yaml", "base: " + BaseName(middle) + "\ncount: 9\n");
  SampleConfig config;
  ReadConfig(LoadConfigFile(top.path()), "top", config);
  EXPECT_EQ(config.count, 9);
  EXPECT_DOUBLE_EQ(config.rate, 0.75);
  SampleConfig middle_config;
  ReadConfig(LoadConfigFile(middle.path()), "middle", middle_config);
  EXPECT_EQ(middle_config.count, 2);
}

TEST(LoadConfigFile, ACycleOfBasesIsAnError) {
  const std::string dir = std::filesystem::path(testutil::UniqueTempPath("cycle")).string();
  std::filesystem::create_directories(dir);
  std::ofstream(dir + "/a.yaml") << "base: b.yaml\ncount: 1\n";
  std::ofstream(dir + "/b.yaml") << "base: a.yaml\ncount: 2\n";
  EXPECT_THAT(InputErrorMessage([&] { LoadConfigFile(dir + "/a.yaml"); }),
              AllOf(HasSubstr("base: a cycle"), HasSubstr("a.yaml -> "), HasSubstr("b.yaml")));
  std::filesystem::remove_all(dir);
}

TEST(LoadConfigFile, AMissingBaseNamesTheIncludingFileAndTheBase) {
  const TempFile file(".yaml", "base: no_such_base.yaml\n");
  EXPECT_THAT(InputErrorMessage([&] { LoadConfigFile(file.path()); }),
              AllOf(HasSubstr("no_such_base.yaml"), HasSubstr("cannot open")));
}

TEST(LoadConfigFile, OverridesSetValuesListsAndNewSections) {
  const TempFile file(".yaml", "count: 4\ninner:\n  gain: 0.1\n");
  SampleConfig config;
  ReadConfig(LoadConfigFile(file.path(), {"count=7", "inner.span=[0.25, 0.5]", "verbose=true", "name=x=y"}), "f",
             config);
  EXPECT_EQ(config.count, 7);
  EXPECT_DOUBLE_EQ(config.inner.gain, 0.1);
  EXPECT_EQ(config.inner.span, (Interval{0.25, 0.5}));
  EXPECT_TRUE(config.verbose);
  EXPECT_EQ(config.name, "x=y");  // the first '=' ends the key

  const TempFile bare(".yaml", "count: 4\n");
  SampleConfig nested;
  ReadConfig(LoadConfigFile(bare.path(), {"inner.gain=0.9"}), "f", nested);  // no inner: in the file
  EXPECT_DOUBLE_EQ(nested.inner.gain, 0.9);
}

TEST(LoadConfigFile, MalformedOverridesAreNamed) {
  const TempFile file(".yaml", "count: 4\n");
  for (const std::string bad : {"count", "=3", "inner..gain=1", ".count=1", "count.=1"}) {
    EXPECT_THAT(InputErrorMessage([&] { LoadConfigFile(file.path(), {bad}); }),
                AllOf(HasSubstr("--set '" + bad + "'"), HasSubstr("key.path=value")))
        << bad;
  }
  EXPECT_THAT(InputErrorMessage([&] { LoadConfigFile(file.path(), {"count.sub=1"}); }),
              HasSubstr("count is a value, not a section"));
  EXPECT_THAT(InputErrorMessage([&] { LoadConfigFile(file.path(), {"count=[1, 2"}); }),
              HasSubstr("the value is not YAML"));
  // An unknown key passes the loader and is named by the strict reader.
  SampleConfig config;
  EXPECT_THAT(InputErrorMessage([&] { ReadConfig(LoadConfigFile(file.path(), {"cuont=5"}), "f:", config); }),
              HasSubstr("f: cuont: unknown key"));
}

TEST(LoadConfigSection, MissingSectionIsNamed) {
  const TempFile file(".yaml", "other: {}\n");
  EXPECT_THAT(InputErrorMessage([&] { LoadConfigSection<EnvConfig>(file.path(), "env"); }),
              AllOf(HasSubstr(file.path()), HasSubstr("missing section 'env'")));
}

TEST(EnvConfigYaml, NestedUnknownKeyIsNamedWithItsFullPath) {
  const TempFile file(".yaml",
                      "env:\n"
                      "  randomization:\n"
                      "    friction:\n"
                      "      rnage: [0.1, 0.2]\n");
  EXPECT_THAT(InputErrorMessage([&] { LoadConfigSection<EnvConfig>(file.path(), "env"); }),
              AllOf(HasSubstr(file.path() + ": env.randomization.friction.rnage"),
                    HasSubstr("known keys: enabled, range")));
}

TEST(EnvConfigYaml, NestedValuesAreReadAndOthersKeepDefaults) {
  const TempFile file(".yaml",
                      "env:\n"
                      "  episode_steps: 200\n"
                      "  randomization:\n"
                      "    friction: {range: [0.2, 0.3]}\n"
                      "    push: {enabled: false, interval_s: 4}\n");
  const EnvConfig c = LoadConfigSection<EnvConfig>(file.path(), "env");
  const EnvConfig defaults;
  EXPECT_EQ(c.episode_steps, 200);
  EXPECT_EQ(c.randomization.friction.range, (Interval{0.2, 0.3}));
  EXPECT_TRUE(c.randomization.friction.enabled);
  EXPECT_FALSE(c.randomization.push.enabled);
  EXPECT_EQ(c.randomization.push.interval_s, 4.0);
  EXPECT_EQ(c.randomization.restitution.range, defaults.randomization.restitution.range);
  EXPECT_EQ(c.reset.joint_pos_scale, defaults.reset.joint_pos_scale);
  EXPECT_EQ(c.model, defaults.model);
}

TEST(EnvConfigYaml, RandomRangeOutsideItsAllowedBoundsIsRejected) {
  const TempFile file(".yaml", "env:\n  randomization:\n    friction: {range: [0.0, 6.0]}\n");
  EXPECT_THAT(InputErrorMessage([&] { LoadConfigSection<EnvConfig>(file.path(), "env"); }),
              AllOf(HasSubstr("env.randomization.friction.range"), HasSubstr("within [0, 5]"),
                    HasSubstr("got [0, 6]")));
}

TEST(EnvConfigYaml, ToYamlRoundTripPreservesEveryField) {
  EnvConfig original;
  original.model = "elsewhere/scene.xml";
  original.episode_steps = 321;
  original.reset.joint_pos_scale = {0.9, 1.1};
  original.termination.on_calf_contact = true;
  original.termination.limits.max_tilt = 0.7;
  original.randomization.DisableAll();
  original.randomization.motor_strength.range = {0.8, 1.2};
  original.randomization.push.max_velocity = 0.3;

  const std::string text = ToYamlString(original);
  EXPECT_NE(text, ToYamlString(EnvConfig{}));
  EnvConfig back;
  ReadConfig(YAML::Load(text), "round trip", back);
  EXPECT_EQ(ToYamlString(back), text);
  EXPECT_EQ(back.model, original.model);
  EXPECT_EQ(back.episode_steps, 321);
  EXPECT_TRUE(back.termination.on_calf_contact);
  EXPECT_FALSE(back.randomization.friction.enabled);
  EXPECT_EQ(back.randomization.motor_strength.range, (Interval{0.8, 1.2}));
}

}  // namespace
}  // namespace flsd
