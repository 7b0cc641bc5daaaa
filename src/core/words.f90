!> The one word splitter of the input readers: what a blank is, and where the word that starts
!> at a position ends. The scene lexer (scene_parser: comments, quotes, continuations on top)
!> and the data-file reader (line_reader: Gmsh meshes, result files on a restart) split with it.
module words
  implicit none
  private
  public :: is_blank, word_end

  character(len=*), parameter :: TAB = achar(9), LF = achar(10), CR = achar(13)

contains

  !> A blank separates words: space, tab, and CR (a CR LF line end leaves its CR in the line).
  pure logical function is_blank(c)
    character, intent(in) :: c
    is_blank = c == ' ' .or. c == TAB .or. c == CR
  end function is_blank

  !> The position just past the word that starts at text(i:i): the first blank, line feed or
  !> character of `stops` (the scene's '#' comments) from i on, or len(text) + 1.
  pure integer function word_end(text, i, stops) result(j)
    character(len=*), intent(in) :: text
    integer, intent(in) :: i
    character(len=*), intent(in), optional :: stops
    character :: c
    j = i
    do while (j <= len(text))
      c = text(j:j)
      if (is_blank(c) .or. c == LF) exit
      if (present(stops)) then
        if (index(stops, c) > 0) exit
      end if
      j = j + 1
    end do
  end function word_end
end module words
