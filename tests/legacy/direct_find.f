      subroutine direct_find(itimestep, ntotal, hsml, x, niac, pair_i,
     &                       pair_j, w, dwdx, countiac)
c-----------------------------------------------------------------------
c     All pairs closer than the kernel's support, by testing every
c     particle against every other one (order N**2), with the kernel
c     value and gradient of each pair.
c     itimestep -- number of the current time step                 (in)
c     ntotal    -- number of particles                             (in)
c     hsml      -- smoothing lengths                               (in)
c     x         -- positions                                       (in)
c     niac      -- number of pairs found                          (out)
c     pair_i    -- first particle of each pair                    (out)
c     pair_j    -- second particle of each pair (pair_j > pair_i) (out)
c     w         -- kernel of each pair                            (out)
c     dwdx      -- kernel gradient of each pair                   (out)
c     countiac  -- number of neighbours of each particle          (out)
c-----------------------------------------------------------------------
      implicit none
      include 'param.inc'
      integer itimestep, ntotal, niac, pair_i(max_interaction),
     &        pair_j(max_interaction), countiac(maxn)
      double precision hsml(maxn), x(dim,maxn), w(max_interaction),
     &        dwdx(dim,max_interaction)
      integer i, j, d, kappa, nsum, nmost
      double precision sep(dim), r2, r, hij, grad(dim)
c     search statistics, shared with time_integration
      integer nsearch, npairmax
      common /nnstat/ nsearch, npairmax
c     calls of this routine so far (kept from call to call)
      integer ncall
      save ncall
      data ncall /0/

      ncall = ncall + 1
      if (skf .eq. 1) then
        kappa = 2
      else
        kappa = 3
      endif

      do 10 i = 1, ntotal
        countiac(i) = 0
   10 continue

      niac = 0
      do 40 i = 1, ntotal - 1
        do 30 j = i + 1, ntotal
          sep(1) = x(1,i) - x(1,j)
          r2 = sep(1)*sep(1)
          do 20 d = 2, dim
            sep(d) = x(d,i) - x(d,j)
            r2 = r2 + sep(d)*sep(d)
   20     continue
          hij = (hsml(i) + hsml(j))/2.
          if (sqrt(r2) .lt. kappa*hij) then
            if (niac .ge. max_interaction) then
              write(*,*) ' direct_find: too many interactions'
              stop
            endif
            niac = niac + 1
            pair_i(niac) = i
            pair_j(niac) = j
            countiac(i) = countiac(i) + 1
            countiac(j) = countiac(j) + 1
            r = sqrt(r2)
            call kernel(r, sep, hij, w(niac), grad)
            do 25 d = 1, dim
              dwdx(d,niac) = grad(d)
   25       continue
          endif
   30   continue
   40 continue

      nsearch = ncall
      if (niac .gt. npairmax) npairmax = niac

      if (mod(itimestep, print_step) .eq. 0) then
        nsum = 0
        nmost = 0
        do 50 i = 1, ntotal
          nsum = nsum + countiac(i)
          if (countiac(i) .gt. nmost) nmost = countiac(i)
   50   continue
        write(*,*) ' pairs:', niac, '  most neighbours:', nmost,
     &             '  mean:', real(nsum)/real(ntotal)
      endif

      end
