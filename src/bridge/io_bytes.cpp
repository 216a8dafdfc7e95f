/*
 * io_bytes.cpp: the whole-file I/O of the mesh bridge (see mesh_io_int.hpp): the one-line
 * messages of every read and write failure, errno as a lower-case phrase, opening a
 * regular file and reading it whole or a piece at a time, and the atomic write every writer ends with: the bytes go to
 * a temporary file in the target's folder, are fsync'ed and renamed over the target, the
 * folder fsync'ed; on failure nothing is left behind.
 */
#include "bridge/mesh_io_int.hpp"

#include <atomic>
#include <cerrno>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <string>
#include <sys/stat.h>
#include <unistd.h>

namespace sr_meshio {

namespace {

sr_status vfail(sr_err *err, sr_status st, const char *verb, const char *path, const char *fmt,
                va_list ap)
{
    if (err) {
        char detail[400];
        vsnprintf(detail, sizeof detail, fmt, ap);
        sr_err_set(err, st, "cannot %s '%s': %s", verb, path, detail);
    }
    return st;
}

} // namespace

sr_status rfail(sr_err *err, sr_status st, const char *path, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vfail(err, st, "read", path, fmt, ap);
    va_end(ap);
    return st;
}

sr_status wfail(sr_err *err, sr_status st, const char *path, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vfail(err, st, "write", path, fmt, ap);
    va_end(ap);
    return st;
}

/* errno as a lower-case phrase. */
std::string errno_text(int e)
{
    switch (e) {
    case ENOENT: return "no such file";
    case ENOTDIR: return "a path component is not a directory";
    case EACCES: case EPERM: return "permission denied";
    case EISDIR: return "is a directory";
    case ENAMETOOLONG: return "name too long";
    case ELOOP: return "too many symbolic links";
    case EROFS: return "read-only file system";
    case ENOSPC: return "no space left on device";
    case EDQUOT: return "disk quota exceeded";
    default: break;
    }
    std::string s = strerror(e);
    if (!s.empty() && s[0] >= 'A' && s[0] <= 'Z')
        s[0] = (char)(s[0] - 'A' + 'a');
    return s;
}

/* First line of a library's message, shortened. */
std::string first_line(const std::string &s)
{
    size_t a = s.find_first_not_of(" \t\r\n");
    if (a == std::string::npos)
        return "no detail";
    size_t b = s.find_first_of("\r\n", a);
    std::string l = s.substr(a, b == std::string::npos ? std::string::npos : b - a);
    if (l.size() > 160)
        l.replace(157, std::string::npos, "...");
    return l;
}

sr_status open_regular(const char *path, size_t limit, int *fd_out, size_t *size_out, sr_err *err)
{
    int fd = open(path, O_RDONLY | O_CLOEXEC | O_NOCTTY | O_NONBLOCK);
    if (fd < 0)
        return rfail(err, SR_E_IO, path, "%s", errno_text(errno).c_str());
    struct stat st;
    sr_status rc = SR_OK;
    if (fstat(fd, &st) != 0)
        rc = rfail(err, SR_E_IO, path, "%s", errno_text(errno).c_str());
    else if (S_ISDIR(st.st_mode))
        rc = rfail(err, SR_E_IO, path, "is a directory");
    else if (!S_ISREG(st.st_mode))
        rc = rfail(err, SR_E_IO, path, "not a regular file");
    else if (st.st_size == 0)
        rc = rfail(err, SR_E_IO, path, "empty file");
    else if ((unsigned long long)st.st_size > limit)
        rc = rfail(err, SR_E_UNSUPPORTED, path, "file too large (%lld bytes; %s %zu bytes)",
                   (long long)st.st_size,
                   limit == MESH_FILE_MAX ? "mesh files are limited to 2 GiB," : "at most", limit);
    if (rc != SR_OK) {
        close(fd);
        return rc;
    }
    *fd_out = fd;
    *size_out = (size_t)st.st_size;
    return SR_OK;
}

sr_status read_at(int fd, size_t offset, void *buf, size_t n, const char *path, sr_err *err)
{
    size_t got = 0;
    while (got < n) {
        ssize_t r = pread(fd, (unsigned char *)buf + got, n - got, (off_t)(offset + got));
        if (r < 0 && errno == EINTR)
            continue;
        if (r <= 0) {
            if (r < 0)
                return rfail(err, SR_E_IO, path, "%s", errno_text(errno).c_str());
            return rfail(err, SR_E_IO, path, "file shrank while being read");
        }
        got += (size_t)r;
    }
    return SR_OK;
}

sr_status read_whole(int fd, size_t size, const char *path, Bytes &out, sr_err *err)
{
    unsigned char *buf = (unsigned char *)malloc(size + 1);
    if (!buf)
        return rfail(err, SR_E_NOMEM, path, "out of memory for %zu bytes", size);
    sr_status st = read_at(fd, 0, buf, size, path, err);
    if (st != SR_OK) {
        free(buf);
        return st;
    }
    buf[size] = 0;
    out.data = buf;
    out.size = size;
    return SR_OK;
}

/* Reads a whole regular, non-empty file of at most `limit` bytes (NUL appended). */
sr_status read_file(const char *path, size_t limit, Bytes &out, sr_err *err)
{
    int fd;
    size_t size;
    sr_status st = open_regular(path, limit, &fd, &size, err);
    if (st != SR_OK)
        return st;
    st = read_whole(fd, size, path, out, err);
    close(fd);
    return st;
}

std::string dir_of(const std::string &path)
{
    size_t slash = path.find_last_of('/');
    if (slash == std::string::npos)
        return ".";
    if (slash == 0)
        return "/";
    return path.substr(0, slash);
}

namespace {

std::atomic<unsigned> temp_counter{0};

} // namespace

/* Writes bytes to path atomically: a new temporary file in the same folder, fsync,
 * rename over path, fsync of the folder. On failure nothing is left behind. */
sr_status AtomicFile::open(const char *path, sr_err *err)
{
    path_ = path;
    std::string dir = dir_of(path);
    for (int attempt = 0; attempt < 100 && fd_ < 0; attempt++) {
        tmp_ = dir + "/.symrec-" + std::to_string((long)getpid()) + "-" +
               std::to_string(temp_counter++) + ".tmp";
        fd_ = ::open(tmp_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (fd_ < 0 && errno != EEXIST)
            break;
    }
    if (fd_ < 0) {
        int e = errno;
        struct stat st;
        if ((e == ENOENT || e == ENOTDIR) && stat(dir.c_str(), &st) != 0)
            return wfail(err, SR_E_IO, path, "no such directory '%s'", dir.c_str());
        return wfail(err, SR_E_IO, path, "%s", errno_text(e).c_str());
    }
    return SR_OK;
}

bool AtomicFile::write(const void *bytes, size_t size)
{
    const unsigned char *p = (const unsigned char *)bytes;
    size_t done = 0;
    while (!errno_ && done < size) {
        ssize_t n = ::write(fd_, p + done, size - done);
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0)
            errno_ = n < 0 ? errno : EIO;
        else
            done += (size_t)n;
    }
    return !errno_;
}

sr_status AtomicFile::commit(sr_err *err)
{
    int e = errno_;
    if (!e && fsync(fd_) != 0)
        e = errno;
    if (close(fd_) != 0 && !e)
        e = errno;
    fd_ = -1;
    if (!e && rename(tmp_.c_str(), path_.c_str()) != 0)
        e = errno;
    if (e) {
        unlink(tmp_.c_str());
        return wfail(err, SR_E_IO, path_.c_str(), "%s", errno_text(e).c_str());
    }
    committed_ = true;
    int dfd = ::open(dir_of(path_).c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (dfd >= 0) {
        fsync(dfd);   /* best effort: some file systems refuse fsync on a directory */
        close(dfd);
    }
    return SR_OK;
}

AtomicFile::~AtomicFile()
{
    if (fd_ >= 0)
        close(fd_);
    if (!committed_ && !tmp_.empty())
        unlink(tmp_.c_str());
}

sr_status write_file_atomic(const char *path, const void *bytes, size_t size, sr_err *err)
{
    AtomicFile f;
    sr_status st = f.open(path, err);
    if (st != SR_OK)
        return st;
    f.write(bytes, size);
    return f.commit(err);
}

} // namespace sr_meshio
