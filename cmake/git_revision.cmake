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
cmake_policy(SET CMP0007 NEW)  # (list(REMOVE_ITEM) of the empty item)

# The first 12 hex digits of the SHA-256 of the files' (paths relative to SRC, sorted) paths and
# contents ("deleted" for a path that is not a file).
function(hash_files out)
  set(files ${ARGN})
  list(SORT files)
  list(REMOVE_DUPLICATES files)
  set(state "")
  foreach(f IN LISTS files)
    if(EXISTS "${SRC}/${f}" AND NOT IS_DIRECTORY "${SRC}/${f}")
      file(SHA256 "${SRC}/${f}" h)
    else()
      set(h "deleted")
    endif()
    string(APPEND state "${f}\n${h}\n")
  endforeach()
  string(SHA256 h "${state}")
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
  string(SHA256 h "${sums}")
  string(SUBSTRING "${h}" 0 12 h)
  set(rev "no-git-${h}")
else()
  execute_process(COMMAND git -C "${SRC}" -c core.quotepath=off diff HEAD --name-only --no-renames
                  OUTPUT_VARIABLE changed ERROR_QUIET)
  execute_process(COMMAND git -C "${SRC}" -c core.quotepath=off ls-files --others
                          --exclude-standard
                  OUTPUT_VARIABLE untracked ERROR_QUIET)
  string(REPLACE "\n" ";" files "${changed}${untracked}")
  list(REMOVE_ITEM files "")
  if(files)
    hash_files(h ${files})
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
