// The README's headline table (tools/bench/headline.h): made from a report's
// CSV text, so planted rows must come out in it, and a malformed file must
// be refused with its line, never half-read.
#include <catch2/catch.hpp>
#include <string>

#include "tools/bench/headline.h"

namespace bitstep::bench {

namespace {

const std::string results_header =
    "experiment,group,variant,dt,iterations,error,failed,ms_per_step,ms_per_simulated_s,metrics\n";

// Every shown experiment on bitstep's default and Bullet; stack50's Bullet
// run fell.
std::string planted_results() {
  std::string csv = results_header;
  for (const char* name :
       {"free_fall", "pendulum", "chain_stretch", "stack50", "wall128", "thrown", "heavy_on_light"}) {
    csv += std::string(name) + ",g,standard+shock,0.0166,10,0.25,0,1.5,90,\"a=1, b=2\"\n";
    csv += std::string(name) + ",g,standard,0.0166,10,99,1,9,9,\n";  // another variant: not shown
    csv += std::string(name) + ",g,bullet,0.0166,10," + (std::string(name) == "stack50" ? "53.7,1" : "0.5,0") +
           ",3,180,\n";
  }
  return csv;
}

// Two cases: bitstep's medians 1 and 3, Bullet's 2 and 1 (ratios 0.5 and 3).
const std::string planted_speed =
    "scene,phase,from_step,steps,round,bitstep_cpu_ms_per_step,bullet_cpu_ms_per_step\n"
    "a.json,standing,60,20,1,1,2\n"
    "a.json,standing,60,20,2,1,2\n"
    "b.json,impact,0,20,1,3,1\n"
    "b.json,impact,0,20,2,3,1\n";

}  // namespace

TEST_CASE("the headline table shows bitstep's default and Bullet from the report's rows", "[bench]") {
  const Result<std::string> block = headline_block(planted_results(), planted_speed);
  REQUIRE(block.ok());
  const std::string& md = block.value();
  CHECK(md.rfind(std::string(headline_begin), 0) == 0);
  CHECK(md.find("| 50 unit cubes | max drift (m) | 0.25 | 53.7 fell | 1.5 | 3 |") != std::string::npos);
  CHECK(md.find("| free fall from rest, 2 s | abs(y - exact) after 2 s (m) | 0.25 | 0.5 | 1.5 | 3 |") !=
        std::string::npos);
  CHECK(md.find("99") == std::string::npos);       // the other variant's figures
  CHECK(md.find("(quick:") == std::string::npos);  // the full run's description
  CHECK(md.find("2 cases of a scene and a phase (standing, impact)") != std::string::npos);
  CHECK(md.find("0.50x to 3.00x") != std::string::npos);
  CHECK(md.find("median 1.75x") != std::string::npos);
  CHECK(md.size() - md.rfind(std::string(headline_end)) == headline_end.size() + 1);
}

TEST_CASE("the headline table refuses a report it cannot read whole, naming the file and line", "[bench]") {
  const std::string speed = planted_speed;
  SECTION("a row of the wrong width") {
    const Result<std::string> block = headline_block(results_header + "free_fall,g,bullet\n", speed);
    REQUIRE_FALSE(block.ok());
    CHECK(block.error().message() == "results.csv: line 2: 3 fields, the header has 10");
  }
  SECTION("a figure that is not a number") {
    std::string csv = planted_results();
    csv.replace(csv.find("0.25"), 4, "0.2x");
    const Result<std::string> block = headline_block(csv, speed);
    REQUIRE_FALSE(block.ok());
    CHECK(block.error().message() == "results.csv: line 2: error is '0.2x', not a number");
  }
  SECTION("a shown experiment missing") {
    std::string csv = results_header;
    const Result<std::string> block = headline_block(csv, speed);
    REQUIRE_FALSE(block.ok());
    CHECK(block.error().message() == "results.csv: no row for free_fall");
  }
  SECTION("an unclosed quote in the speed file") {
    const Result<std::string> block = headline_block(planted_results(), speed + "c.json,\"settled,1,2\n");
    REQUIRE_FALSE(block.ok());
    CHECK(block.error().message() == "speed.csv: line 6: a quoted field is not closed");
  }
}

TEST_CASE("the headline block replaces exactly the lines between the README's markers", "[bench]") {
  const std::string begin(headline_begin), end(headline_end);
  const std::string readme = "# title\n\n" + begin + "\nold table\n" + end + "\n\n## next\n";
  const Result<std::string> updated = with_headline(readme, begin + "\nnew table\n" + end + "\n");
  REQUIRE(updated.ok());
  CHECK(updated.value() == "# title\n\n" + begin + "\nnew table\n" + end + "\n\n## next\n");
  // Written again, the same text: the check compares it with the file.
  CHECK(with_headline(updated.value(), begin + "\nnew table\n" + end + "\n").value() == updated.value());
  CHECK_FALSE(with_headline("# no markers\n", "x").ok());
  CHECK_FALSE(with_headline(end + "\n" + begin + "\n", "x").ok());
}

}  // namespace bitstep::bench
