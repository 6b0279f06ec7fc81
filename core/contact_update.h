// The narrowphase pass of the step: this step's contacts from the broadphase
// pairs, each matched with last step's contact of the same key so that its
// points inherit their accumulated impulses by feature id.
#pragma once

#include <vector>

#include "core/broadphase.h"
#include "core/body.h"
#include "core/contact.h"

namespace bitstep {

// `contacts` holds last step's contacts on entry and this step's on return,
// both sorted by key. `previous` is workspace (last step's contacts are moved
// there while this step's are found), kept by the caller so that a settled
// step allocates nothing.
void update_contacts(const std::vector<Body>& bodies, const std::vector<BodyPair>& pairs, const Settings& settings,
                     std::vector<Contact>& contacts, std::vector<Contact>& previous);

}  // namespace bitstep
