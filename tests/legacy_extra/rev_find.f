      subroutine rev_find(itimestep, ntotal, hsml, x, niac, pair_i,
     &                    pair_j, w, dwdx, countiac)
c-----------------------------------------------------------------------
c     The pairs of direct_find in another order and the other way
c     round: j from the last particle down, each pair stored as (j, i)
c     with j > i, its kernel gradient taken from x(j) - x(i).
c     (A second search for the tests of blastsph: a pair list that is
c     to be compared with blastsph's as a set.)
c-----------------------------------------------------------------------
      implicit none
      include 'param.inc'
      integer itimestep, ntotal, niac, pair_i(max_interaction),
     &        pair_j(max_interaction), countiac(maxn)
      double precision hsml(maxn), x(dim,maxn), w(max_interaction),
     &        dwdx(dim,max_interaction)
      integer i, j, d
      double precision sep(dim), r2, r, hij, grad(dim)

      do 10 i = 1, ntotal
        countiac(i) = 0
   10 continue
      niac = 0
      do 40 i = 1, ntotal - 1
        do 30 j = ntotal, i + 1, -1
          sep(1) = x(1,j) - x(1,i)
          r2 = sep(1)*sep(1)
          do 20 d = 2, dim
            sep(d) = x(d,j) - x(d,i)
            r2 = r2 + sep(d)*sep(d)
   20     continue
          hij = (hsml(i) + hsml(j))/2.
          if (sqrt(r2) .lt. 2*hij) then
            niac = niac + 1
            pair_i(niac) = j
            pair_j(niac) = i
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
      end
