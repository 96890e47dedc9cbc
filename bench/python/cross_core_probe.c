// How dear it is on this machine for one core to take over memory the other core just wrote:
// two threads pinned to CPUs 0 and 1 (1) bounce one cache line, and (2) take turns writing
// every line of a 1 MiB buffer, against one thread doing (2) alone; then (3) two threads
// left where the scheduler puts them (as a server's and its client's are) send one byte back
// and forth over a loopback TCP connection with Nagle off, each blocked in `read` until its
// turn: the floor under any unary call between two processes here, before gRPC adds its own
// work; and (4) the same with both threads pinned to CPU 0, where a wake-up needs no other
// core. Prints one line:
//   round_trip_ns=… other_core_ns_per_line=… same_core_ns_per_line=… tcp_round_trip_us=…
//   tcp_same_core_us=…
// Built and run by `cross_core_ab.py`; `gcc -O2 -pthread cross_core_probe.c -o probe` alone.
#define _GNU_SOURCE
#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <pthread.h>
#include <sched.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

#define BYTES (1 << 20)
#define BOUNCES 1000000L
#define ROUNDS 400
#define TCP_EXCHANGES 5000

static _Atomic long line __attribute__((aligned(64)));
static _Atomic int turn;
static volatile long *buf;

static void pin(int cpu) {
    cpu_set_t set;
    CPU_ZERO(&set);
    CPU_SET(cpu, &set);
    pthread_setaffinity_np(pthread_self(), sizeof set, &set);
}

static double now_ns(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return t.tv_sec * 1e9 + t.tv_nsec;
}

static void touch(void) {
    for (long i = 0; i < BYTES / 8; i += 8) buf[i] += 1;
}

static void *bounce(void *arg) {
    (void)arg;
    pin(1);
    for (long i = 0; i < BOUNCES; i++) {
        while (atomic_load_explicit(&line, memory_order_acquire) != 2 * i + 1) {}
        atomic_store_explicit(&line, 2 * i + 2, memory_order_release);
    }
    return 0;
}

static void *take_turns(void *arg) {
    int me = (int)(long)arg;
    pin(me);
    for (int r = 0; r < ROUNDS; r++) {
        while (atomic_load(&turn) != 2 * r + me) {}
        touch();
        atomic_store(&turn, 2 * r + me + 1);
    }
    return 0;
}

static int no_delay(int fd) {
    int one = 1;
    setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
    return fd;
}

static void *echo(void *arg) {
    int fd = no_delay(accept((int)(long)arg, 0, 0));
    char byte;
    while (read(fd, &byte, 1) == 1 && write(fd, &byte, 1) == 1) {}
    close(fd);
    return 0;
}

// Microseconds per round trip of one byte over loopback TCP; -1 if a socket call failed.
static double tcp_round_trip_us(void) {
    struct sockaddr_in addr = {.sin_family = AF_INET, .sin_addr.s_addr = htonl(INADDR_LOOPBACK)};
    socklen_t len = sizeof addr;
    int listener = socket(AF_INET, SOCK_STREAM, 0);
    if (listener < 0 || bind(listener, (void *)&addr, len) || listen(listener, 1) ||
        getsockname(listener, (void *)&addr, &len))
        return -1;
    pthread_t server;
    pthread_create(&server, 0, echo, (void *)(long)listener);
    int fd = no_delay(socket(AF_INET, SOCK_STREAM, 0));
    if (fd < 0 || connect(fd, (void *)&addr, len)) return -1;
    char byte = 'x';
    double t0 = now_ns();
    for (int i = 0; i < TCP_EXCHANGES; i++)
        if (write(fd, &byte, 1) != 1 || read(fd, &byte, 1) != 1) return -1;
    double us = (now_ns() - t0) / TCP_EXCHANGES / 1e3;
    close(fd);
    pthread_join(server, 0);
    close(listener);
    return us;
}

int main(void) {
    cpu_set_t all;
    sched_getaffinity(0, sizeof all, &all);
    pthread_t a, b;
    pthread_create(&a, 0, bounce, 0);
    pin(0);
    double t0 = now_ns();
    for (long i = 0; i < BOUNCES; i++) {
        atomic_store_explicit(&line, 2 * i + 1, memory_order_release);
        while (atomic_load_explicit(&line, memory_order_acquire) != 2 * i + 2) {}
    }
    double round_trip = (now_ns() - t0) / BOUNCES;
    pthread_join(a, 0);

    buf = aligned_alloc(64, BYTES);
    for (long i = 0; i < BYTES / 8; i++) buf[i] = 0;
    double lines = 2.0 * ROUNDS * BYTES / 64;
    t0 = now_ns();
    pthread_create(&a, 0, take_turns, (void *)0);
    pthread_create(&b, 0, take_turns, (void *)1);
    pthread_join(a, 0);
    pthread_join(b, 0);
    double other = (now_ns() - t0) / lines;
    t0 = now_ns();
    for (int r = 0; r < 2 * ROUNDS; r++) touch();
    double same = (now_ns() - t0) / lines;
    // The echo thread inherits the creating thread's CPUs.
    double tcp_same = tcp_round_trip_us();
    pthread_setaffinity_np(pthread_self(), sizeof all, &all);
    double tcp = tcp_round_trip_us();
    printf("round_trip_ns=%.0f other_core_ns_per_line=%.2f same_core_ns_per_line=%.2f "
           "tcp_round_trip_us=%.1f tcp_same_core_us=%.1f\n",
           round_trip, other, same, tcp, tcp_same);
    return 0;
}
