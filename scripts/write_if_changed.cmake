# write_if_changed(PATH TEXT): writes TEXT to PATH only if PATH holds something
# else, so that a generated header's users rebuild only when it changes.
function(write_if_changed path text)
  set(old "")
  if(EXISTS ${path})
    file(READ ${path} old)
  endif()
  if(NOT "${old}" STREQUAL "${text}")
    file(WRITE ${path} "${text}")
  endif()
endfunction()
