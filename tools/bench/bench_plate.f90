!> QUAD4 plane-strain plate benchmark of the core solver (make bench, tools/bench.sh).
!> usage: bench_plate NX NY NSTEPS NSOLVE WORKDIR [NREP [NZ]]
!> (NZ > 0: a 3D steel block of NX x NY x NZ HEX8 instead of the plate, 1 m x 1 m x NZ/NX m, clamped on
!> x = 0 and its face x = 1 launched: DIMENSION 3, the same library calls.)
!> Writes WORKDIR/plate_NXxNY.dat (a steel plate clamped on its left edge, its right edge
!> launched with an initial velocity, no output in the loop), then times through the library:
!> load_scene, build_system, prepare_run (analysis + factorization of S = K0 + 4M/h²), NREP
!> numeric refactorizations of S (median), then NREP times (default 3): NSOLVE bare solves on that same
!> factor (median) and run_newmark over NSTEPS steps. Times are CPU times (cpu_time: the
!> machine is shared, wall-clock time is noise); the solve and run_newmark figures are the best
!> of the NREP rounds. A replay of the step (same library calls, same order) gives the median
!> CPU time of a step, which the ratio step/solve divides by the median solve, and splits it
!> (median over the steps of each part); internal_force is the sparse product K0 u
!> (stiffness_product), and the element loop it replaces is timed beside it (t_kmv). The last line, "RESULT k=v ...",
!> is read by bench.sh.
program bench_plate
  use, intrinsic :: iso_fortran_env, only: int64
  use kinds, only: dp
  use errors, only: STAT_OK
  use scene, only: scene_t
  use scene_loader, only: load_scene
  use assembly, only: system_t, build_system, external_force, commit_state
  use newmark, only: run_options_t, run_summary_t, run_state_t, prepare_run, run_newmark
  use cholmod_binding, only: factor_stats_t, ORDERING_NAMES, blas_threads
  implicit none

  ! Parts of a replayed step, in run_newmark's order.
  integer, parameter :: P_EXT = 1, P_VEC = 2, P_SOLVE = 3, P_FINT = 4, P_COMMIT = 5, P_MASS = 6, NPART = 6
  character(len=14), parameter :: PART_NAME(NPART) = [character(len=14) :: 'external_force', 'vector ops', &
    'solve', 'internal_force', 'commit_state', 'eq (3), M v']
  character(len=*), parameter :: PART_KEY(NPART) = [character(len=6) :: 't_ext', 't_vec', 't_slv', 't_fint', &
    't_comm', 't_mass']

  type(scene_t) :: scn
  type(system_t) :: sys
  type(run_state_t) :: rs
  type(run_options_t) :: opts
  type(run_summary_t) :: summary
  character(len=:), allocatable :: errmsg, workdir, path, ordname
  character(len=512), allocatable :: overrides(:)
  integer :: nx, ny, nz, nsteps, nsolve, nrep, rep, stat, i, k, minor, unit
  real(dp) :: lnz, xsize, fl
  type(factor_stats_t) :: fst
  real(dp) :: t0, t_load, t_build, t_analyze, t_prepare, t_factor, t_step, t_solve, h, dw, kin
  real(dp) :: part(NPART), tp, t_kmv, kdiff, t_rmed, ratio_own
  integer :: th_solve, th_factor
  real(dp), allocatable :: b(:), x(:), ts(:), steps_t(:, :), solve_rep(:), step_rep(:), t_rstep(:), fac_rep(:)
  character(len=256) :: hw_prepare

  nx = int_arg(1)
  ny = int_arg(2)
  nsteps = int_arg(3)
  nsolve = int_arg(4)
  workdir = str_arg(5)
  nrep = 3
  if (command_argument_count() >= 6) nrep = int_arg(6)
  nz = 0
  if (command_argument_count() >= 7) nz = int_arg(7)
  h = 1.0e-6_dp
  allocate (overrides(0))

  ! Scene: 1 m x 1 m steel plate, 10 mm thick, plane strain, consistent mass (NZ > 0: the 3D block).
  path = workdir // '/plate_' // itoa(nx) // 'x' // itoa(ny) // '.dat'
  open (newunit=unit, file=path, status='replace', action='write')
  if (nz > 0) then
    path = workdir // '/block_' // itoa(nx) // 'x' // itoa(ny) // 'x' // itoa(nz) // '.dat'
    close (unit, status='delete')
    open (newunit=unit, file=path, status='replace', action='write')
    write (unit, '(a)') 'TITLE "HEX8 block benchmark"'
    write (unit, '(a)') 'DIMENSION 3'
    write (unit, '(a,es23.16,a)') 'BOX plate ORIGIN 0 0 0 SIZE 1 1 ', real(nz, dp) / nx, ' ELEMENTS ' // itoa(nx) // ' ' // &
      itoa(ny) // ' ' // itoa(nz) // ' TYPE HEX8'
    write (unit, '(a)') 'MATERIAL steel ELASTIC YOUNG 2.1e11 POISSON 0.3 DENSITY 7800'
    write (unit, '(a)') 'MODEL plate MATERIAL steel MASS CONSISTENT'
    write (unit, '(a)') 'FIX plate.xmin UX UY UZ'
    write (unit, '(a)') 'INITIAL plate.xmax VELOCITY 0 -1 0'
  else
    write (unit, '(a)') 'TITLE "QUAD4 plane-strain plate benchmark"'
    write (unit, '(a)') 'DIMENSION 2'
    write (unit, '(a)') 'RECTANGLE plate ORIGIN 0 0 SIZE 1 1 ELEMENTS ' // itoa(nx) // ' ' // itoa(ny) // ' TYPE QUAD4'
    write (unit, '(a)') 'MATERIAL steel ELASTIC YOUNG 2.1e11 POISSON 0.3 DENSITY 7800'
    write (unit, '(a)') 'SECTION plate_sec THICKNESS 0.01'
    write (unit, '(a)') 'MODEL plate MATERIAL steel SECTION plate_sec MASS CONSISTENT PLANE STRAIN'
    write (unit, '(a)') 'FIX plate.left UX UY'
    write (unit, '(a)') 'INITIAL plate.right VELOCITY 0 -1'
  end if
  write (unit, '(a,es23.16,a,es23.16)') 'TIME STEP ', h, ' END ', nsteps * h
  write (unit, '(a)') 'SCHEME NEWMARK'
  write (unit, '(a)') 'OUTPUT HISTORY 0 FIELDS 0'
  close (unit)

  t0 = wall()
  call load_scene(path, overrides, scn, stat, errmsg)
  call check('load_scene')
  t_load = wall() - t0

  t0 = wall()
  call build_system(scn, sys, stat, errmsg)
  call check('build_system')
  t_build = wall() - t0
  write (*, '(a,i0,a,i0,a,i0,a,i0,a)') 'plate ', nx, ' x ', ny, ': ', sys%dofs%neq, ' DOFs, nnz(K, upper) = ', sys%ops%pat%nnz

  ! prepare_run: CHOLMOD analysis (ordering, symbolic) + numeric factorization + initial state.
  t0 = wall()
  call prepare_run(scn, sys, rs, stat, errmsg)
  call check('prepare_run')
  t_prepare = wall() - t0
  hw_prepare = vm_hwm()
  ! What the factor's analysis made (the shim's own figures: ordering, fill, flops, CPU time).
  fst = rs%mat%factor%stats()
  lnz = fst%nnz
  xsize = fst%stored
  fl = fst%flops
  t_analyze = fst%analysis_cpu
  ordname = '?'
  if (fst%ordering > 0) ordname = trim(ORDERING_NAMES(fst%ordering))
  do k = 1, len(ordname)                    ! one word in the RESULT line
    if (ordname(k:k) == ' ') ordname(k:k) = '-'
  end do

  ! Numeric factorization alone: same pattern, so CHOLMOD only refactorizes (median of NREP).
  allocate (fac_rep(nrep))
  do rep = 1, nrep
    t0 = wall()
    call rs%mat%factor%factorize(sys%ops%pat, rs%mat%sval, stat, errmsg, minor)
    call check('refactorize')
    fac_rep(rep) = wall() - t0
  end do
  t_factor = median(fac_rep)

  ! Rounds of bare solves on the factor the run uses (random right-hand side) and of the run
  ! itself (no history, no fields, quiet; each round continues the motion). The first solve
  ! allocates CHOLMOD's workspaces: warm-up, not timed.
  allocate (b(sys%dofs%neq), x(sys%dofs%neq), ts(nsolve * nrep), solve_rep(nrep), step_rep(nrep))
  call random_number(b)
  b = b - 0.5_dp
  call rs%mat%factor%solve(b, x, stat, errmsg)
  call check('solve')
  opts%quiet = .true.
  do rep = 1, nrep
    ! One directory per round: csv_file_t%close does not close newunit (negative) units, so
    ! the files of an earlier round stay open in this process.
    opts%outdir = workdir // '/out_' // itoa(nx) // 'x' // itoa(ny) // '_' // itoa(rep)
    do k = 1, nsolve
      t0 = wall()
      call rs%mat%factor%solve(b, x, stat, errmsg)
      ts((rep - 1) * nsolve + k) = wall() - t0
      call check('solve')
    end do
    solve_rep(rep) = median(ts((rep - 1) * nsolve + 1:rep * nsolve))
    t0 = wall()
    call run_newmark(scn, sys, rs, opts, summary, stat, errmsg)
    call check('run_newmark')
    step_rep(rep) = (wall() - t0) / summary%steps
  end do
  t_solve = median(ts)                      ! every solve of every round: a median, as for the step
  t_step = minval(step_rep)

  ! Replay of the linear step of run_newmark, part by part, to see where the step goes.
  allocate (steps_t(nsteps, NPART), t_rstep(nsteps))
  do i = 1, nsteps
    part = 0.0_dp
    tp = wall()
    call external_force(scn, sys, scn%t_start + i * h, rs%st%f_np1)
    call lap(P_EXT)
    call rs%st%begin_step()                 ! the right-hand side of (9), r = rhs - Bσ(n)
    call lap(P_VEC)
    call rs%mat%solve(rs%st%r, rs%st%ddu, stat, errmsg)
    call lap(P_SOLVE)
    rs%st%du = rs%st%du + rs%st%ddu
    call lap(P_VEC)
    call rs%st%trial(scn, sys, scn%energy_correction)   ! Bσ(n+1) of u(n) + du
    call lap(P_FINT)
    call commit_state(sys)
    call lap(P_COMMIT)
    dw = 0.5_dp * dot_product(rs%st%du, rs%st%f_n + rs%st%f_np1)
    call rs%st%velocity(sys)                ! eq (3) and M v(n+1)
    call lap(P_MASS)
    call rs%st%commit(sys)
    call lap(P_VEC)
    kin = rs%st%kinetic
    steps_t(i, :) = part
    t_rstep(i) = sum(part)
  end do
  do k = 1, NPART
    part(k) = median(steps_t(:, k))
  end do

  ! The step takes Bσ(u) = K0 u (stiffness_product) for this linear elastic model: time the
  ! element loop it replaces, the same internal_force call with the product off, and check that
  ! both give the same vector on the last state.
  t_rmed = median(t_rstep)
  ! The same ratio within each step (its own solve part), immune to the load changing between the
  ! rounds of bare solves and the replay: median over the steps of step / its solve.
  ratio_own = median(t_rstep / max(steps_t(:, P_SOLVE), tiny(1.0_dp)))
  call sys%ops%k0u%disable()
  do i = 1, nsteps
    t0 = wall()
    call rs%st%trial(scn, sys, scn%energy_correction)
    steps_t(i, 1) = wall() - t0
  end do
  t_kmv = median(steps_t(:, 1))
  rs%st%du = 0.0_dp                         ! Bσ at the committed u
  call rs%st%trial(scn, sys, scn%energy_correction)
  b = rs%st%fint
  call sys%ops%k0u%enable()
  call rs%st%trial(scn, sys, scn%energy_correction)
  kdiff = norm2(rs%st%fint - b) / max(norm2(b), tiny(1.0_dp))

  write (*, '(a,f10.3,a)') '  load_scene            ', t_load, ' s'
  write (*, '(a,f10.3,a)') '  build_system          ', t_build, ' s'
  write (*, '(a,f10.3,a)') '  prepare_run           ', t_prepare, ' s  (analysis + factorization + initial state)'
  write (*, '(a,f10.3,a)') '    of which analysis   ', t_analyze, ' s  (ordering ' // ordname // ', symbolic)'
  write (*, '(a,f10.3,a,i0,a)') '  numeric factorization ', t_factor, ' s  (median of ', nrep, ')'
  write (*, '(a,f8.3)') '  setup / factorization ', (t_load + t_build + t_prepare) / t_factor
  write (*, '(a,es10.3,a,i0,a)') '  bare solve            ', t_solve, ' s  (median of ', nrep * nsolve, ' solves)'
  write (*, '(a,*(es10.3))') '    rounds:             ', solve_rep
  write (*, '(a,es10.3,a,i0,a,i0,a)') '  step (run_newmark)    ', t_step, ' s  (best of ', nrep, ' runs of ', &
    summary%steps, ' steps)'
  write (*, '(a,*(es10.3))') '    rounds:             ', step_rep
  write (*, '(a,es10.3,a)') '  replayed step         ', t_rmed, ' s  (median over the steps)'
  write (*, '(a,f8.3)') '  ratio step / solve    ', t_rmed / t_solve
  write (*, '(a,f8.3)') '  ratio step / its solve', ratio_own
  write (*, '(a,es10.3,a,es10.3,a,es10.3,a)') '  nnz(L) = ', lnz, ' (stored ', xsize, '), factor flops ', fl, &
    ', ordering ' // ordname
  write (*, '(a)') '  replayed step (median over the steps of each part):'
  do i = 1, NPART
    write (*, '(4x,a,es10.3,a,f6.1,a)') PART_NAME(i), part(i), ' s ', 100.0_dp * part(i) / sum(part), ' %'
  end do
  write (*, '(4x,a,es10.3,a)') 'total         ', sum(part), ' s'
  write (*, '(a,es10.3,a,es9.2,a)') '  element loop          ', t_kmv, ' s; |K0 u - element loop| / |.| = ', &
    kdiff, ' (linear elastic: the same vector)'
  write (*, '(a,a,a,a)') '  VmHWM after prepare_run ', trim(hw_prepare), ' kB, at end ', trim(vm_hwm()) // ' kB'
  write (*, '(a,es10.3,a,es10.3,a)') '  (replay end: kinetic energy ', kin, ' J, last external work ', dw, ' J)'

  write (*, '(a)', advance='no') 'RESULT nx=' // itoa(nx) // ' ny=' // itoa(ny) // ' nz=' // itoa(nz) // &
    ' ndof=' // itoa(sys%dofs%neq) // &
    ' nnzk=' // itoa(sys%ops%pat%nnz) // ' steps=' // itoa(summary%steps) // ' nsolve=' // itoa(nsolve) // &
    ' lnz=' // rtoa(lnz) // ' xsize=' // rtoa(xsize) // ' flops=' // rtoa(fl) // ' ordering=' // ordname // &
    ' t_load=' // rtoa(t_load) // ' t_build=' // rtoa(t_build) // ' t_analyze=' // rtoa(t_analyze) // &
    ' t_prepare=' // rtoa(t_prepare) // ' t_factor=' // rtoa(t_factor) // ' t_solve=' // rtoa(t_solve) // &
    ' t_step=' // rtoa(t_step) // ' t_step_median=' // rtoa(t_rmed) // ' ratio=' // rtoa(t_rmed / t_solve) // &
    ' ratio_own=' // rtoa(ratio_own) // &
    ' nrep=' // itoa(nrep) // &
    ' t_solve_max=' // rtoa(maxval(solve_rep)) // ' t_step_max=' // rtoa(maxval(step_rep)) // &
    ' t_kmv=' // rtoa(t_kmv) // ' kdiff=' // rtoa(kdiff)
  do i = 1, NPART
    write (*, '(a)', advance='no') ' ' // trim(PART_KEY(i)) // '=' // rtoa(part(i))
  end do
  call blas_threads(th_solve, th_factor)
  write (*, '(a)') ' hwm_prepare_kb=' // trim(hw_prepare) // ' hwm_kb=' // trim(vm_hwm()) // &
    ' blas_solve=' // itoa(th_solve) // ' blas_factor=' // itoa(th_factor)
  call rs%mat%factor%destroy()

contains

  !> CPU time of the process in seconds (the machine is shared: wall-clock time is noise; the
  !> step and the solve run on one thread, so their CPU times compare).
  real(dp) function wall()
    call cpu_time(wall)
  end function wall

  !> Add the time since tp to part p and restart the lap.
  subroutine lap(p)
    integer, intent(in) :: p
    real(dp) :: t
    t = wall()
    part(p) = part(p) + (t - tp)
    tp = t
  end subroutine lap

  subroutine check(what)
    character(len=*), intent(in) :: what
    if (stat == STAT_OK) return
    write (0, '(a)') 'bench_plate: ' // what // ': ' // errmsg
    error stop 1
  end subroutine check

  real(dp) function median(a)
    real(dp), intent(in) :: a(:)
    real(dp) :: s(size(a)), v
    integer :: i, j
    s = a
    do i = 2, size(s)
      v = s(i)
      j = i - 1
      do while (j >= 1)
        if (s(j) <= v) exit
        s(j + 1) = s(j)
        j = j - 1
      end do
      s(j + 1) = v
    end do
    median = 0.5_dp * (s((size(s) + 1) / 2) + s(size(s) / 2 + 1))
  end function median

  !> Peak resident memory (VmHWM, kB) of this process, from /proc/self/status.
  function vm_hwm() result(s)
    character(len=256) :: s
    character(len=256) :: line
    integer :: u, ios
    s = '?'
    open (newunit=u, file='/proc/self/status', status='old', action='read', iostat=ios)
    if (ios /= 0) return
    do
      read (u, '(a)', iostat=ios) line
      if (ios /= 0) exit
      if (line(1:6) == 'VmHWM:') then
        line = line(7:)
        do while (index(line, achar(9)) > 0)
          line(index(line, achar(9)):index(line, achar(9))) = ' '
        end do
        s = adjustl(line)
        s = s(1:index(s, ' ') - 1)
        exit
      end if
    end do
    close (u)
  end function vm_hwm

  function rtoa(x) result(s)
    real(dp), intent(in) :: x
    character(len=:), allocatable :: s
    character(len=24) :: buf
    write (buf, '(es12.5)') x
    s = trim(adjustl(buf))
  end function rtoa

  function itoa(i) result(s)
    integer, intent(in) :: i
    character(len=:), allocatable :: s
    character(len=24) :: buf
    write (buf, '(i0)') i
    s = trim(buf)
  end function itoa

  function str_arg(k) result(a)
    integer, intent(in) :: k
    character(len=:), allocatable :: a
    integer :: l
    call get_command_argument(k, length=l)
    if (l == 0) then
      write (0, '(a)') 'usage: bench_plate NX NY NSTEPS NSOLVE WORKDIR [NREP]'
      error stop 2
    end if
    allocate (character(len=l) :: a)
    call get_command_argument(k, a)
  end function str_arg

  integer function int_arg(k)
    integer, intent(in) :: k
    integer :: ios
    character(len=:), allocatable :: a
    a = str_arg(k)
    read (a, *, iostat=ios) int_arg
    if (ios /= 0 .or. int_arg < 1) then
      write (0, '(a)') 'bench_plate: argument ' // itoa(k) // ' must be a positive integer'
      error stop 2
    end if
  end function int_arg
end program bench_plate
