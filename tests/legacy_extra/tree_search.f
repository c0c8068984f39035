      subroutine tree_search(itimestep, ntotal, hsml, x, niac, pair_i,
     &                       pair_j, w, dwdx, countiac)
c-----------------------------------------------------------------------
c     All pairs closer than the kernel's support, found with a tree.
c     The bounding box of the particles is bisected in every direction
c     (a binary tree in 1D, a quadtree in 2D, an octree in 3D) until a
c     cell holds at most nleaf particles.  Each particle i then walks
c     the tree from the root with a stack, skips the cells out of its
c     reach and tests the particles j > i of the leaves it reaches
c     with the test of direct_find.  The pairs come in the order of
c     the walk: i ascending, then the leaves as the stack gives them.
c     (A third search for the tests of blastsph, written for them.)
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
c     nleaf    : most particles of a leaf
c     maxdepth : deepest level (particles at one place stay together)
c     maxnode  : most cells of the tree
c     nchild   : children of a cell, 2**dim
      integer nleaf, maxdepth, maxnode, nchild
      parameter (nleaf = 4, maxdepth = 40, maxnode = 4*maxn,
     &           nchild = 2**dim)
c     the tree: cell k spans lo(.,k) .. hi(.,k), its particles are
c     idx(first(k)), ..., idx(first(k) + npart(k) - 1), hmax(k) is
c     their largest h; kid(c,k) are its children (0: none) and nkid(k)
c     their number (0 for a leaf)
      double precision lo(dim,maxnode), hi(dim,maxnode), hmax(maxnode)
      integer first(maxnode), npart(maxnode), depth(maxnode),
     &        kid(nchild,maxnode), nkid(maxnode), idx(maxn), tmp(maxn),
     &        ord(maxn), stack(maxnode), nin(nchild), start(nchild)
      integer nnode, top, i, j, k, m, c, d, bit, kappa, nsum, nmost
      double precision sep(dim), r2, r, hij, grad(dim), mid, e, dmin2,
     &        reach
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

c     the root: the bounding box of all particles
      nnode = 1
      do 10 d = 1, dim
        lo(d,1) = x(d,1)
        hi(d,1) = x(d,1)
   10 continue
      do 20 i = 1, ntotal
        idx(i) = i
        countiac(i) = 0
        do 15 d = 1, dim
          if (x(d,i) .lt. lo(d,1)) lo(d,1) = x(d,i)
          if (x(d,i) .gt. hi(d,1)) hi(d,1) = x(d,i)
   15   continue
   20 continue
      first(1) = 1
      npart(1) = ntotal
      depth(1) = 0

c     split the cells in the order they were made (breadth first)
      k = 0
   30 continue
      k = k + 1
      if (k .gt. nnode) goto 100
      hmax(k) = 0.
      do 35 m = first(k), first(k) + npart(k) - 1
        if (hsml(idx(m)) .gt. hmax(k)) hmax(k) = hsml(idx(m))
   35 continue
      nkid(k) = 0
      do 40 c = 1, nchild
        kid(c,k) = 0
        nin(c) = 0
   40 continue
      if (npart(k) .le. nleaf .or. depth(k) .ge. maxdepth) goto 30
c     the child of each particle: bit d set when above the middle in d
      do 50 m = first(k), first(k) + npart(k) - 1
        j = idx(m)
        c = 1
        bit = 1
        do 45 d = 1, dim
          mid = (lo(d,k) + hi(d,k))/2.
          if (x(d,j) .ge. mid) c = c + bit
          bit = 2*bit
   45   continue
        ord(m) = c
        nin(c) = nin(c) + 1
   50 continue
c     the particles of the children one after the other, in the order
c     they had in the cell
      start(1) = first(k)
      do 55 c = 2, nchild
        start(c) = start(c-1) + nin(c-1)
   55 continue
      do 70 m = first(k), first(k) + npart(k) - 1
        c = ord(m)
        tmp(start(c)) = idx(m)
        start(c) = start(c) + 1
   70 continue
      do 75 m = first(k), first(k) + npart(k) - 1
        idx(m) = tmp(m)
   75 continue
c     a cell for each child that has particles: half the box in each d
      m = first(k)
      do 90 c = 1, nchild
        if (nin(c) .eq. 0) goto 90
        if (nnode .ge. maxnode) then
          write(*,*) ' tree_search: too many cells'
          stop
        endif
        nnode = nnode + 1
        nkid(k) = nkid(k) + 1
        kid(c,k) = nnode
        first(nnode) = m
        npart(nnode) = nin(c)
        depth(nnode) = depth(k) + 1
        m = m + nin(c)
        bit = 1
        do 85 d = 1, dim
          mid = (lo(d,k) + hi(d,k))/2.
          if (mod((c - 1)/bit, 2) .eq. 1) then
            lo(d,nnode) = mid
            hi(d,nnode) = hi(d,k)
          else
            lo(d,nnode) = lo(d,k)
            hi(d,nnode) = mid
          endif
          bit = 2*bit
   85   continue
   90 continue
      goto 30

c     the walk of each particle
  100 continue
      niac = 0
      do 200 i = 1, ntotal
        top = 1
        stack(1) = 1
  110   continue
        if (top .eq. 0) goto 200
        k = stack(top)
        top = top - 1
c       the distance from x(.,i) to the box of cell k, squared
        dmin2 = 0.
        do 120 d = 1, dim
          e = 0.
          if (x(d,i) .lt. lo(d,k)) e = lo(d,k) - x(d,i)
          if (x(d,i) .gt. hi(d,k)) e = x(d,i) - hi(d,k)
          dmin2 = dmin2 + e*e
  120   continue
c       out of reach of every particle of the cell (with a margin far
c       above the rounding of both sides)
        reach = kappa*(hsml(i) + hmax(k))/2.
        if (dmin2 .gt. 1.000001d0*reach*reach) goto 110
        if (nkid(k) .gt. 0) then
          do 130 c = 1, nchild
            if (kid(c,k) .ne. 0) then
              top = top + 1
              stack(top) = kid(c,k)
            endif
  130     continue
          goto 110
        endif
c       a leaf: the test of direct_find for its particles above i
        do 150 m = first(k), first(k) + npart(k) - 1
          j = idx(m)
          if (j .le. i) goto 150
          sep(1) = x(1,i) - x(1,j)
          r2 = sep(1)*sep(1)
          do 140 d = 2, dim
            sep(d) = x(d,i) - x(d,j)
            r2 = r2 + sep(d)*sep(d)
  140     continue
          hij = (hsml(i) + hsml(j))/2.
          if (sqrt(r2) .lt. kappa*hij) then
            if (niac .ge. max_interaction) then
              write(*,*) ' tree_search: too many interactions'
              stop
            endif
            niac = niac + 1
            pair_i(niac) = i
            pair_j(niac) = j
            countiac(i) = countiac(i) + 1
            countiac(j) = countiac(j) + 1
            r = sqrt(r2)
            call kernel(r, sep, hij, w(niac), grad)
            do 145 d = 1, dim
              dwdx(d,niac) = grad(d)
  145       continue
          endif
  150   continue
        goto 110
  200 continue

      nsearch = ncall
      if (niac .gt. npairmax) npairmax = niac

      if (mod(itimestep, print_step) .eq. 0) then
        nsum = 0
        nmost = 0
        do 210 i = 1, ntotal
          nsum = nsum + countiac(i)
          if (countiac(i) .gt. nmost) nmost = countiac(i)
  210   continue
        write(*,*) ' pairs:', niac, '  most neighbours:', nmost,
     &             '  mean:', real(nsum)/real(ntotal)
      endif

      end
