!> Metrics of one sweep case, measured on its output files (probes.csv, events.csv), and their
!> errors against a reference. The kernels are pure and work on plain arrays; case_metrics
!> reads the files and fills the metric columns of a sweep_t (docs/sweep.md).
module sweep_metrics
  use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan, ieee_is_nan
  use kinds, only: dp
  use array_utils, only: bracket
  use errors, only: STAT_OK, STAT_RUN, set_error
  use scene_parser, only: read_text
  use number_text, only: parse_real_text, NUM_OK
  use os_utils, only: path_exists
  use sweep_spec, only: sweep_t, text_t, MK_APEX, MK_CONTACT_DURATION, MK_ONSETS, MK_PROBE
  implicit none
  private
  public :: find_apexes, interp_at, contact_periods, metric_error, nan_value
  public :: read_csv_columns, case_metrics

contains

  pure real(dp) function nan_value()
    nan_value = ieee_value(0.0_dp, ieee_quiet_nan)
  end function nan_value

  !> The first size(yap) local maxima of y(t) (y(k) > y(k-1) and y(k) >= y(k+1), interior
  !> samples), each refined by the parabola through samples k-1, k, k+1: with
  !> p(t) = y_k + s (t - t_k) + a (t - t_k)², a the second divided difference and s = p'(t_k),
  !> the apex is at t_k - s/2a with height y_k - s²/4a. For motion that is exactly quadratic
  !> between the samples (free flight under gravity) this is exact. A sample that is not
  !> strictly concave (a >= 0) is kept as it is. n is the number found (<= size(yap)).
  pure subroutine find_apexes(t, y, tap, yap, n)
    real(dp), intent(in) :: t(:), y(:)
    real(dp), intent(out) :: tap(:), yap(:)
    integer, intent(out) :: n
    integer :: k
    real(dp) :: d1, d2, a, s
    n = 0
    tap = nan_value()
    yap = nan_value()
    do k = 2, size(y) - 1
      if (n == size(yap)) exit
      if (.not. (y(k) > y(k - 1) .and. y(k) >= y(k + 1))) cycle
      n = n + 1
      d1 = (y(k) - y(k - 1)) / (t(k) - t(k - 1))
      d2 = (y(k + 1) - y(k)) / (t(k + 1) - t(k))
      a = (d2 - d1) / (t(k + 1) - t(k - 1))
      if (a < 0.0_dp) then
        s = d1 + a * (t(k) - t(k - 1))
        tap(n) = t(k) - s / (2.0_dp * a)
        yap(n) = y(k) - s * s / (4.0_dp * a)
      else
        tap(n) = t(k)
        yap(n) = y(k)
      end if
    end do
  end subroutine find_apexes

  !> y(tq) by linear interpolation between the samples around tq (t increasing); NaN outside.
  pure real(dp) function interp_at(t, y, tq) result(v)
    real(dp), intent(in) :: t(:), y(:), tq
    integer :: lo, hi
    v = nan_value()
    if (size(t) == 0) return
    if (tq < t(1) .or. tq > t(size(t))) return
    if (size(t) == 1) then
      v = y(1)
      return
    end if
    lo = min(bracket(t, tq), size(t) - 1)      ! t(lo) <= tq <= t(hi)
    hi = lo + 1
    if (tq == t(lo)) then
      v = y(lo)
    else if (tq == t(hi)) then
      v = y(hi)
    else
      v = y(lo) + (y(hi) - y(lo)) * ((tq - t(lo)) / (t(hi) - t(lo)))
    end if
  end function interp_at

  !> Impacts from contact events (time order): the number of active conditions goes up at an
  !> establish event and down at a release (never below 0); a contact period runs from the
  !> establish that makes it positive to the release that brings it back to 0, and periods
  !> separated by at most `gap` belong to the same impact (a quick re-contact, chatter).
  !> For impact i: tstart(i), tend(i) (NaN if the run ends in contact) and nest(i), the number
  !> of establish events. n impacts in all (arrays sized by the caller, size(t) is enough).
  pure subroutine contact_periods(t, establish, gap, tstart, tend, nest, n)
    real(dp), intent(in) :: t(:)
    logical, intent(in) :: establish(:)
    real(dp), intent(in) :: gap
    real(dp), intent(out) :: tstart(:), tend(:)
    integer, intent(out) :: nest(:), n
    integer :: k, active
    n = 0
    active = 0
    tstart = nan_value()
    tend = nan_value()
    nest = 0
    do k = 1, size(t)
      if (establish(k)) then
        if (active == 0) then
          ! a new impact unless the last one ended less than `gap` ago
          if (n == 0) then
            n = n + 1
            tstart(n) = t(k)
          else if (ieee_is_nan(tend(n))) then
            n = n + 1
            tstart(n) = t(k)
          else if (t(k) - tend(n) > gap) then
            n = n + 1
            tstart(n) = t(k)
          end if
          tend(n) = nan_value()
        end if
        active = active + 1
        nest(n) = nest(n) + 1
      else if (active > 0) then
        active = active - 1
        if (active == 0) tend(n) = t(k)
      end if
    end do
  end subroutine contact_periods

  !> Error of x against ref: |x - ref| / scale when scale > 0, else relative |x - ref| / |ref|,
  !> absolute when ref = 0. NaN when either is NaN.
  elemental real(dp) function metric_error(x, ref, scale) result(e)
    real(dp), intent(in) :: x, ref, scale
    if (ieee_is_nan(x) .or. ieee_is_nan(ref)) then
      e = nan_value()
    else if (scale > 0.0_dp) then
      e = abs(x - ref) / scale
    else if (ref /= 0.0_dp) then
      e = abs(x - ref) / abs(ref)
    else
      e = abs(x - ref)
    end if
  end function metric_error

  !> Columns `names` of a CSV file with a header line, as text (rows, columns). Fields are split
  !> at commas (rebond's CSV files never quote).
  subroutine read_csv_columns(path, names, fields, stat, errmsg)
    character(len=*), intent(in) :: path
    type(text_t), intent(in) :: names(:)
    type(text_t), allocatable, intent(out) :: fields(:, :)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    character(len=:), allocatable :: text
    integer, allocatable :: col(:)
    integer :: nlines, p, q, e, row, c, j, nparts
    type(text_t), allocatable :: parts(:)
    character(len=1), parameter :: LF = achar(10)
    call read_text(path, text, stat, errmsg)
    if (stat /= STAT_OK) return
    nlines = 0
    do p = 1, len(text)
      if (text(p:p) == LF) nlines = nlines + 1
    end do
    if (len(text) > 0) then
      if (text(len(text):len(text)) /= LF) nlines = nlines + 1
    end if
    if (nlines == 0) then
      call set_error(stat, errmsg, STAT_RUN, path // ': empty file')
      return
    end if
    ! header
    e = index(text, LF)
    if (e == 0) e = len(text) + 1
    allocate (col(size(names)))
    col = 0
    call split_csv(text(1:e - 1), parts, nparts)
    do c = 1, nparts
      do j = 1, size(names)
        if (trim(parts(c)%s) == names(j)%s) col(j) = c
      end do
    end do
    do j = 1, size(names)
      if (col(j) == 0) then
        call set_error(stat, errmsg, STAT_RUN, path // ': no column ' // names(j)%s)
        return
      end if
    end do
    allocate (fields(nlines - 1, size(names)))
    row = 0
    p = e + 1
    do while (p <= len(text))
      q = index(text(p:), LF)
      if (q == 0) then
        q = len(text) + 1
      else
        q = p + q - 1
      end if
      if (q > p) then
        row = row + 1
        call split_csv(text(p:q - 1), parts, nparts)
        do j = 1, size(names)
          if (col(j) > nparts) then
            call set_error(stat, errmsg, STAT_RUN, path // ': short line ' // text(p:q - 1))
            return
          end if
          fields(row, j)%s = parts(col(j))%s
        end do
      end if
      p = q + 1
    end do
    if (row < size(fields, 1)) fields = fields(1:row, :)
  end subroutine read_csv_columns

  !> The fields of one CSV line (RFC 4180: a field between double quotes may hold commas, and ""
  !> stands for a quote), unquoted, in parts(1:n); parts grows as needed.
  subroutine split_csv(line, parts, n)
    character(len=*), intent(in) :: line
    type(text_t), allocatable, intent(inout) :: parts(:)
    integer, intent(out) :: n
    type(text_t), allocatable :: tmp(:)
    character(len=len(line)) :: buf
    integer :: i, k
    logical :: quoted
    if (.not. allocated(parts)) allocate (parts(16))
    n = 0
    k = 0
    quoted = .false.
    i = 1
    do while (i <= len(line) + 1)
      if (i <= len(line)) then
        if (quoted) then
          if (line(i:i) == '"') then
            if (i < len(line)) then
              if (line(i + 1:i + 1) == '"') then
                k = k + 1
                buf(k:k) = '"'
                i = i + 2
                cycle
              end if
            end if
            quoted = .false.
          else
            k = k + 1
            buf(k:k) = line(i:i)
          end if
          i = i + 1
          cycle
        end if
        if (line(i:i) == '"' .and. k == 0) then
          quoted = .true.
          i = i + 1
          cycle
        end if
        if (line(i:i) /= ',') then
          k = k + 1
          buf(k:k) = line(i:i)
          i = i + 1
          cycle
        end if
      end if
      n = n + 1                                    ! a comma, or the end of the line
      if (n > size(parts)) then
        allocate (tmp(2 * size(parts)))
        tmp(1:size(parts)) = parts
        call move_alloc(tmp, parts)
      end if
      parts(n)%s = buf(1:k)
      k = 0
      i = i + 1
    end do
  end subroutine split_csv

  !> Numeric column j of fields (NaN where a field is not a number).
  function numeric(fields, j) result(x)
    type(text_t), intent(in) :: fields(:, :)
    integer, intent(in) :: j
    real(dp), allocatable :: x(:)
    integer :: i, ierr
    allocate (x(size(fields, 1)))
    do i = 1, size(x)
      call parse_real_text(trim(adjustl(fields(i, j)%s)), x(i), ierr)
      if (ierr /= NUM_OK) x(i) = nan_value()
    end do
  end function numeric

  !> Every metric column of sw for the run written in outdir with step h (values(:) sized to
  !> size(sw%columns); NaN where a metric has no value, e.g. fewer apexes than asked).
  subroutine case_metrics(sw, outdir, h, values, stat, errmsg)
    type(sweep_t), intent(in) :: sw
    character(len=*), intent(in) :: outdir
    real(dp), intent(in) :: h
    real(dp), intent(out) :: values(:)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    type(text_t), allocatable :: f(:, :)
    real(dp), allocatable :: t(:), y(:), tap(:), ts(:), te(:)
    logical, allocatable :: est(:)
    integer, allocatable :: nest(:)
    type(text_t) :: names(2)
    integer :: i, n, k, nimp
    real(dp) :: gap
    stat = STAT_OK
    errmsg = ''
    values = nan_value()
    do i = 1, size(sw%metrics)
      associate (m => sw%metrics(i), v => values(sw%metrics(i)%first_col:sw%metrics(i)%first_col + &
                 sw%metrics(i)%ncol - 1))
        select case (m%kind)
        case (MK_APEX, MK_PROBE)
          names(1)%s = 'time'
          names(2)%s = m%probe
          call read_csv_columns(outdir // '/probes.csv', names, f, stat, errmsg)
          if (stat /= STAT_OK) return
          t = numeric(f, 1)
          y = numeric(f, 2)
          if (m%kind == MK_APEX) then
            allocate (tap(m%count))
            call find_apexes(t, y, tap, v, n)
            deallocate (tap)
          else
            v(1) = interp_at(t, y, m%at)
          end if
        case (MK_CONTACT_DURATION, MK_ONSETS)
          gap = m%gap
          if (gap < 0.0_dp) gap = 10.0_dp * h
          if (path_exists(outdir // '/events.csv')) then
            names(1)%s = 'time'
            names(2)%s = 'event'
            call read_csv_columns(outdir // '/events.csv', names, f, stat, errmsg)
            if (stat /= STAT_OK) return
            t = numeric(f, 1)
            est = [(trim(adjustl(f(k, 2)%s)) == 'establish', k = 1, size(t))]
          else
            t = [real(dp) ::]                       ! a scene without contact: no impact
            est = [logical ::]
          end if
          allocate (ts(max(1, size(t))), te(max(1, size(t))), nest(max(1, size(t))))
          call contact_periods(t, est, gap, ts, te, nest, nimp)
          if (m%kind == MK_CONTACT_DURATION) then
            if (nimp > 0) v(1) = te(1) - ts(1)
          else
            v(1) = real(nimp, dp)
            do k = 1, m%count
              if (k <= nimp) then
                v(1 + k) = real(nest(k), dp)
              else
                v(1 + k) = 0.0_dp
              end if
            end do
          end if
          deallocate (ts, te, nest)
        end select
      end associate
    end do
  end subroutine case_metrics

end module sweep_metrics
