# Writes OUT with `#define SHVOL_GIT_REVISION "<commit>[-dirty-<hash>]"` for the source tree SRC
# ("unknown" outside a git checkout). The tree is dirty when a tracked file differs from the
# commit or a file git does not ignore is untracked (the build globs its sources: a new .cpp is
# compiled before it is added). <hash> is the first 12 hex digits of the SHA-256 of those files'
# paths and contents (or "deleted"), so two builds of one commit with different changes differ
# (a batch refuses rows another build finished; both were "<commit>-dirty"), whatever the user's
# git diff settings (a hash of `git diff` changed with diff.noprefix or color.diff; review). Run
# at every build; the file is rewritten only when the text changes (src/app/git_revision.cpp
# alone includes it).
cmake_policy(SET CMP0007 NEW)  # (list(REMOVE_ITEM) of the empty item)
execute_process(COMMAND git -C "${SRC}" rev-parse HEAD OUTPUT_VARIABLE rev
                OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET RESULT_VARIABLE rc)
if(NOT rc EQUAL 0 OR rev STREQUAL "")
  set(rev "unknown")
else()
  execute_process(COMMAND git -C "${SRC}" -c core.quotepath=off diff HEAD --name-only --no-renames
                  OUTPUT_VARIABLE changed ERROR_QUIET)
  execute_process(COMMAND git -C "${SRC}" -c core.quotepath=off ls-files --others
                          --exclude-standard
                  OUTPUT_VARIABLE untracked ERROR_QUIET)
  string(REPLACE "\n" ";" files "${changed}${untracked}")
  list(REMOVE_ITEM files "")
  if(files)
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
