#include "commands.h"
#include "shvol_git_revision.h"  // (regenerated at every build: only this file includes it)

namespace shvol::app {

const char* gitRevision() {
    return SHVOL_GIT_REVISION;
}

}  // namespace shvol::app
