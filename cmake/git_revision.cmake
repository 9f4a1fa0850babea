# Writes OUT with `#define SHVOL_GIT_REVISION "<commit>[-dirty-<hash>]"` for the source tree SRC.
# The tree is dirty when a tracked file differs from the commit or a file git does not ignore is
# untracked (the build globs its sources: a new .cpp is compiled before it is added). <hash> is
# the first 12 hex digits of the SHA-256 of those files' paths and contents (or "deleted"), so
# two builds of one commit with different changes differ (a batch refuses rows another build
# finished; both were "<commit>-dirty"), whatever the user's git diff settings (a hash of
# `git diff` changed with diff.noprefix or color.diff; review). Outside a git checkout (a source
# archive) it is "no-git-<hash>", <hash> being of the files the program is built from: src/,
# include/, cmake/ and CMakeLists.txt (the builds of two different archives were both "unknown",
# and one resumed the other's checkpoints). Run at every build; the file is rewritten only when
# the text changes (src/app/git_revision.cpp alone includes it).
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

execute_process(COMMAND git -C "${SRC}" rev-parse HEAD OUTPUT_VARIABLE rev
                OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET RESULT_VARIABLE rc)
if(NOT rc EQUAL 0 OR rev STREQUAL "")
  file(GLOB_RECURSE files RELATIVE "${SRC}" "${SRC}/src/*" "${SRC}/include/*" "${SRC}/cmake/*")
  hash_files(h ${files} CMakeLists.txt)
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
