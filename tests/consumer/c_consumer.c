/* The same game loop as cpp_consumer.cpp through the C API: scenes/pyramid20.json
 * with a ball thrown in before tick 10 ends with the hash of
 * scenes/pyramid20.short.replay.json (tools/test.sh checks). */
#include <inttypes.h>
#include <stdio.h>

#include "replay/bitstep.h"

int main(int argc, char** argv) {
  char error[512];
  bitstep_simulation* sim = NULL;
  bitstep_body ball;
  bitstep_pose pose;
  int tick;
  if (argc != 2) {
    fprintf(stderr, "usage: c_consumer SCENE.json\n");
    return 2;
  }
  if (bitstep_create_from_file(argv[1], &sim, error, sizeof error) != BITSTEP_OK) {
    fprintf(stderr, "%s\n", error);
    return 1;
  }
  for (tick = 1; tick <= 20; ++tick) {
    if (tick == 10 &&
        bitstep_add_body(sim,
                         "{\"name\": \"ball\", \"position\": [-8, 3, 0], \"velocity\": [15, 3, 0],"
                         " \"shapes\": [{\"type\": \"sphere\", \"radius\": 0.5}], \"density\": 3000}",
                         &ball) != BITSTEP_OK) {
      fprintf(stderr, "%s\n", bitstep_last_error(sim));
      bitstep_destroy(sim);
      return 1;
    }
    bitstep_step(sim);
  }
  if (bitstep_get_pose(sim, ball, &pose) == BITSTEP_OK) {
    printf("ball at x %.6f y %.6f\n", bitstep_fixed_to_double(pose.position.x), bitstep_fixed_to_double(pose.position.y));
  }
  printf("tick %" PRIu64 " hash %016" PRIx64 "\n", bitstep_tick(sim), bitstep_hash(sim));
  bitstep_destroy(sim);
  return 0;
}
