# Writes OUT with `#define SHVOL_GIT_REVISION "<commit>[-dirty-<hash>]"` for the source tree SRC.
# The tree is dirty when a tracked file differs from the commit or a file git does not ignore is
# untracked (the build globs its sources: a new .cpp is compiled before it is added). <hash> is
# the first 12 hex digits of the SHA-256 of those files' paths and contents (or "deleted"), so
# two builds of one commit with different changes differ (a batch refuses rows another build
# finished; both were "<commit>-dirty"), whatever the user's git diff settings (a hash of
# `git diff` changed with diff.noprefix or color.diff; review). Outside a checkout of its own (a
# source archive, also one unpacked inside another repository's work tree) it is "no-git-<hash>",
# <hash> being of the files the program is built from: src/, include/, cmake/ and CMakeLists.txt
# (the builds of two different archives were both "unknown", and one resumed the other's
# checkpoints). Run at every build; the file is rewritten only when the text changes
# (src/app/git_revision.cpp alone includes it).

# The first 12 hex digits of the SHA-256 of `text`.
function(short_hash out text)
  string(SHA256 h "${text}")
  string(SUBSTRING "${h}" 0 12 h)
  set(${out} "${h}" PARENT_SCOPE)
endfunction()

# A checkout of its own: SRC is the top of the work tree (an archive unpacked inside another
# repository, a home directory under git say, was named by that repository's commit; helper 99).
execute_process(COMMAND git -C "${SRC}" rev-parse HEAD OUTPUT_VARIABLE rev
                OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET RESULT_VARIABLE rc)
execute_process(COMMAND git -C "${SRC}" rev-parse --show-toplevel OUTPUT_VARIABLE top
                OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
get_filename_component(src_real "${SRC}" REALPATH)
if(top)
  get_filename_component(top "${top}" REALPATH)
endif()
if(NOT rc EQUAL 0 OR rev STREQUAL "" OR NOT top STREQUAL src_real)
  # The files' paths and contents through find and sha256sum, NUL-separated: any file name (a
  # CMake list splits at ';' and pairs '[' with ']'), symbolic links not followed, in C order.
  execute_process(COMMAND find src include cmake CMakeLists.txt -type f -print0
                  COMMAND env LC_ALL=C sort -z
                  COMMAND xargs -0 -r sha256sum --
                  WORKING_DIRECTORY "${SRC}" OUTPUT_VARIABLE sums ERROR_QUIET)
  short_hash(h "${sums}")
  set(rev "no-git-${h}")
else()
  # The changed and untracked files' contents (or "deleted") and paths, NUL-separated from git to
  # sha256sum as above: a CMake list of the names hashed "a[1;b.cpp" as two deleted files, so its
  # changes left the name as it was (before 6 Dec).
  execute_process(COMMAND sh -c "{ git diff HEAD --name-only -z --no-renames && \
git ls-files --others --exclude-standard -z; } | LC_ALL=C sort -zu | xargs -0 -r sh -c '\
for f; do if [ -f \"$f\" ]; then sha256sum -- \"$f\"; else printf \"deleted  %s\\n\" \"$f\"; fi; \
done' sh"
                  WORKING_DIRECTORY "${SRC}" OUTPUT_VARIABLE sums ERROR_QUIET)
  if(NOT sums STREQUAL "")
    short_hash(h "${sums}")
    set(rev "${rev}-dirty-${h}")
  endif()
endif()
set(text "#define SHVOL_GIT_REVISION \"${rev}\"\n")
set(old "")
if(EXISTS "${OUT}")
  file(READ "${OUT}" old)
endif()
if(NOT old STREQUAL text)
  file(WRITE "${OUT}" "${text}")
endif()
