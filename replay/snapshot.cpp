#include "replay/snapshot.h"

#include <xxhash.h>

#include <algorithm>

#include "replay/state_bytes.h"
#include "replay/state_description.h"
#include "replay/state_hash.h"

namespace bitstep {

namespace {

constexpr char snapshot_magic[8] = {'B', 'I', 'T', 'S', 'T', 'E', 'P', 'S'};
constexpr size_t snapshot_header_bytes = 8 + 4 + 8;

void put_u32(std::vector<uint8_t>& out, uint32_t v) {
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<uint8_t>(v >> (8 * i)));
}
void put_u64(std::vector<uint8_t>& out, uint64_t v) {
  for (int i = 0; i < 8; ++i) out.push_back(static_cast<uint8_t>(v >> (8 * i)));
}

World read_world(std::span<const uint8_t> payload) {
  state_bytes::ByteReader r(payload);
  OwnedStateParts p;
  describe_state(r, p.refs());
  if (!r.done()) r.fail("bytes left after the state");
  return World::from_state(p.settings, p.step_count, std::move(p.bodies), std::move(p.free_slots),
                           std::move(p.contacts), std::move(p.joints), std::move(p.free_joint_slots),
                           std::move(p.sensor_overlaps), std::move(p.cars), std::move(p.characters));
}

}  // namespace

std::vector<uint8_t> snapshot(const World& world) {
  std::vector<uint8_t> payload;
  serialize_state(world, payload);
  std::vector<uint8_t> image(snapshot_magic, snapshot_magic + 8);
  put_u32(image, snapshot_version);
  put_u64(image, payload.size());
  image.insert(image.end(), payload.begin(), payload.end());
  put_u64(image, XXH3_64bits(image.data(), image.size()));
  return image;
}

Result<void> restore(std::span<const uint8_t> image, World& world) {
  const auto refuse = [](std::string reason) { return Error{{}, std::move(reason)}; };
  if (image.size() < snapshot_header_bytes + 8) return refuse("truncated: " + std::to_string(image.size()) + " bytes is less than a header");
  if (!std::equal(snapshot_magic, snapshot_magic + 8, image.begin())) return refuse("not a bitstep snapshot (bad magic)");
  state_bytes::ByteReader header(image.subspan(8, 12));
  const uint32_t version = header.u32();
  const uint64_t payload_size = header.u64();
  if (version != snapshot_version) {
    return refuse("snapshot format version " + std::to_string(version) + " (this build reads " +
                  std::to_string(snapshot_version) + ")");
  }
  if (payload_size != image.size() - snapshot_header_bytes - 8) {
    return refuse("truncated or padded: the header says " + std::to_string(payload_size) +
                  " payload bytes, the image has " + std::to_string(image.size() - snapshot_header_bytes - 8));
  }
  const size_t body_end = image.size() - 8;
  state_bytes::ByteReader trailer(image.subspan(body_end, 8));
  if (trailer.u64() != XXH3_64bits(image.data(), body_end)) return refuse("checksum mismatch: the image is corrupt");
  try {
    World restored = read_world(image.subspan(snapshot_header_bytes, static_cast<size_t>(payload_size)));
    restored.set_executor(world.executor());  // how it steps, not state: kept
    world = std::move(restored);
  } catch (const Error& corrupt) {  // state_bytes::ByteReader's
    return corrupt;
  }
  return {};
}

}  // namespace bitstep
