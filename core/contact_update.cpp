#include "core/contact_update.h"

#include "core/collide.h"

namespace bitstep {

namespace {

// Copies the accumulated impulses of the old points whose feature ids match.
void inherit_impulses(const Manifold& old, Manifold& fresh) {
  for (int i = 0; i < fresh.point_count; ++i) {
    ContactPoint& p = fresh.points[static_cast<size_t>(i)];
    for (int j = 0; j < old.point_count; ++j) {
      const ContactPoint& q = old.points[static_cast<size_t>(j)];
      if (q.feature != p.feature) continue;
      p.normal_impulse = q.normal_impulse;
      p.tangent_impulse[0] = q.tangent_impulse[0];
      p.tangent_impulse[1] = q.tangent_impulse[1];
      break;
    }
  }
}

}  // namespace

void update_contacts(const std::vector<Body>& bodies, const std::vector<BodyPair>& pairs, const Settings& settings,
                     std::vector<Contact>& contacts) {
  std::vector<Contact> previous;
  previous.swap(contacts);
  size_t next_old = 0;  // both lists are sorted by key: one merge walk
  for (const BodyPair& pair : pairs) {
    const Body& a = bodies[pair.a];
    const Body& b = bodies[pair.b];
    for (size_t sa = 0; sa < a.shapes.size(); ++sa) {
      const WorldShape shape_a{&a.shapes[sa], compose(a.pose, a.shapes[sa].local)};
      for (size_t sb = 0; sb < b.shapes.size(); ++sb) {
        const WorldShape shape_b{&b.shapes[sb], compose(b.pose, b.shapes[sb].local)};
        Contact contact{{pair.a, pair.b, static_cast<uint16_t>(sa), static_cast<uint16_t>(sb)}, {}};
        if (collide(shape_a, shape_b, settings.speculative_distance, contact.manifold) == 0) continue;
        while (next_old < previous.size() && previous[next_old].key < contact.key) ++next_old;
        if (settings.warm_starting && next_old < previous.size() && previous[next_old].key == contact.key) {
          inherit_impulses(previous[next_old].manifold, contact.manifold);
        }
        contacts.push_back(contact);
      }
    }
  }
}

}  // namespace bitstep
