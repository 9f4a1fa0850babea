# Writes OUT with `#define SHVOL_GIT_REVISION "<commit>[-dirty-<hash>]"` for the source tree SRC
# ("unknown" outside a git checkout); <hash> is the first 12 hex digits of the git object hash of
# the tracked files' diff against the commit, so two builds of one commit with different changes
# differ (a batch refuses rows another build finished; they were both "<commit>-dirty"). Run at
# every build; the file is rewritten only when the text changes (src/app/git_revision.cpp alone
# includes it).
execute_process(COMMAND git -C "${SRC}" rev-parse HEAD OUTPUT_VARIABLE rev
                OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET RESULT_VARIABLE rc)
if(NOT rc EQUAL 0 OR rev STREQUAL "")
  set(rev "unknown")
else()
  execute_process(COMMAND git -C "${SRC}" status --porcelain --untracked-files=no
                  OUTPUT_VARIABLE dirty ERROR_QUIET)
  if(NOT dirty STREQUAL "")
    execute_process(COMMAND git -C "${SRC}" diff HEAD --no-ext-diff --binary
                    COMMAND git hash-object --stdin
                    OUTPUT_VARIABLE diff OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
    string(SUBSTRING "${diff}0000000000000" 0 12 diff)
    set(rev "${rev}-dirty-${diff}")
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
